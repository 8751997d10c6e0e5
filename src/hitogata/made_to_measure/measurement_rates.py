"""How fast each measurement changes as the skin moves: the rows of the made-to-measure Jacobian.

Given the skin's motion per unknown (V, 3, K), a girth's tape and a surface
length (`measurement_paths`, polylines on the skin) change to first order by
the motion at their points along the polyline's own directions (a point's
motion is its nearest vertices', inverse-distance weighted); a height above the
floor by its landmark's rise less the lowest skin point's; the mass by the
enclosed volume's gradient. Used by `hitogata.made_to_measure.solve` to steer its
solve, whose residuals are always `measure`'s own values.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from hitogata.body.model import Body
from hitogata.measure import measurement_paths
from hitogata.measure.landmarks import body_landmarks, landmark_positions

HEIGHT_MATCH = 1e-4  # m: a height measurement is a landmark's if it is this close to the landmark's height
NEAREST = 3  # skin vertices that carry a path point's motion


def measurement_rows(body: Body, values: dict[str, float], names: list[str], motion: np.ndarray,
                     density: float) -> np.ndarray:
    """(M, K) first-order change of each named measurement per unit of each unknown, from the skin's
    motion (V, 3, K) (see the module note); a row of NaN for a measurement that is neither a path
    nor a landmark's height above the floor."""
    vertices = body.vertices
    paths = measurement_paths(body)
    tree = cKDTree(vertices)
    floor = int(np.argmin(vertices[:, 1]))
    rows = []
    for name in names:
        if name == "mass":
            rows.append(density * np.einsum("vi,vik->k", volume_gradient(vertices, body.faces), motion))
        elif name in paths:
            rows.append(_path_row(paths[name], tree, motion))
        else:
            rows.append(_height_row(body, values[name], tree, motion, floor))
    return np.array(rows)


def volume_gradient(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(V, 3): the enclosed volume's gradient with respect to each vertex."""
    a, b, c = (vertices[faces[:, i]] for i in range(3))
    grad = np.zeros_like(vertices)
    for i, part in enumerate((np.cross(b, c), np.cross(c, a), np.cross(a, b))):
        np.add.at(grad, faces[:, i], part / 6.0)
    return grad


def _point_motion(points: np.ndarray, tree: cKDTree, motion: np.ndarray) -> np.ndarray:
    """(P, 3, K): the motion at points on the skin, from their nearest vertices (inverse distance)."""
    distance, index = tree.query(points, k=NEAREST)
    weight = 1.0 / np.maximum(distance, 1e-9)
    weight /= weight.sum(axis=1, keepdims=True)
    return np.einsum("pn,pnik->pik", weight, motion[index])


def _path_row(path: np.ndarray, tree: cKDTree, motion: np.ndarray) -> np.ndarray:
    """Change of a polyline's length: each point's motion along the unit vectors of its two segments."""
    step = np.diff(path, axis=0)
    unit = step / np.maximum(np.linalg.norm(step, axis=1, keepdims=True), 1e-12)
    pull = np.zeros_like(path)
    pull[:-1] -= unit
    pull[1:] += unit
    return np.einsum("pi,pik->k", pull, _point_motion(path, tree, motion))


def _height_row(body: Body, value: float, tree: cKDTree, motion: np.ndarray, floor: int) -> np.ndarray:
    """Change of a height above the floor: the landmark at that height rises, the lowest skin point
    sets the floor (NaN if no landmark lies at that height)."""
    vertices = body.vertices
    marks = landmark_positions(body_landmarks(body), vertices)
    heights = {mark: float(p[1] - vertices[floor, 1]) for mark, p in marks.items()}
    mark = min(heights, key=lambda m: abs(heights[m] - value))
    if abs(heights[mark] - value) > HEIGHT_MATCH:
        return np.full(motion.shape[-1], np.nan)
    rise = _point_motion(marks[mark][None, :], tree, motion)[0, 1]
    return rise - motion[floor, 1]
