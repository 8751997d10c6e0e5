"""Points on the skin between its vertices: barycentric landmarks, and paths that start at them.

A landmark found by a ray (acromion, olecranon, ulnar styloid) is the exact
crossing point, kept as barycentric weights of its face's three corners. It
moves continuously as the body's shape changes (a vertex pick jumps by an
edge length — 9–22 mm measured — when the ray moves past the middle of an
edge) and follows the skin into any posture, on any mesh that keeps the
body's vertices first (a subdivided copy, a posed or simulated surface).

Geodesic solvers start paths at vertices, so `insert_points` splits the face
under each point into three, with the point as their shared vertex.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.geometry.closest import barycentric_on_triangles, closest_points_on_triangles

# Barycentric weights are kept at least this far inside a face when the point becomes a
# vertex, so no new triangle is degenerate (moves the point by at most 1e-6 of an edge).
_INSIDE = 1e-6
_CANDIDATES = 16  # triangles with the nearest centroids, whose distance bounds the search


@dataclass(frozen=True)
class SurfacePoint:
    """A point on a face of the body's mesh: its three corner vertices and their weights."""

    corners: tuple[int, int, int]
    weights: tuple[float, float, float]

    def at(self, vertices: np.ndarray) -> np.ndarray:
        """The point (3,) on a surface that shares the body's vertices (rest, posed, subdivided)."""
        return np.asarray(self.weights) @ np.asarray(vertices)[list(self.corners)]

    @classmethod
    def on_face(cls, vertices: np.ndarray, face: np.ndarray, point: np.ndarray) -> SurfacePoint:
        """The point of a triangle (three vertex indices) nearest `point`, as a SurfacePoint."""
        weights = barycentric(vertices[face], point)
        a, b, c = (int(k) for k in face)
        return cls((a, b, c), (float(weights[0]), float(weights[1]), float(weights[2])))

    @classmethod
    def nearest(cls, vertices: np.ndarray, faces: np.ndarray, point: np.ndarray,
                search: FaceSearch | None = None) -> SurfacePoint:
        """The point of the surface nearest `point` (e.g. a point of a planar section); `search`:
        the surface's `FaceSearch`, when several points are wanted."""
        face = faces[(search or FaceSearch(vertices[faces])).nearest(point)]
        return cls.on_face(vertices, face, point)


def barycentric(triangle: np.ndarray, point: np.ndarray) -> np.ndarray:
    """Weights (3,) >= 0, summing to 1, of the triangle's (3, 3) point nearest `point`."""
    a, b, c = triangle
    q = closest_points_on_triangles(point[None], a[None], b[None], c[None])
    return barycentric_on_triangles(q, triangle[None])[0]


class FaceSearch:
    """The triangle (of corners (F, 3, 3)) nearest a point: exact distances only to the
    triangles that can beat the best of the few whose centroids are nearest."""

    def __init__(self, corners: np.ndarray) -> None:
        self.corners = corners
        self.centre = corners.mean(axis=1)
        self.radius = np.linalg.norm(corners - self.centre[:, None], axis=2).max(axis=1)

    def nearest(self, point: np.ndarray) -> int:
        gap = np.linalg.norm(self.centre - point, axis=1)
        first = np.argpartition(gap, min(_CANDIDATES, len(gap) - 1))[:_CANDIDATES]
        rows = np.flatnonzero(gap - self.radius <= _distances(self.corners[first], point).min())
        return int(rows[np.argmin(_distances(self.corners[rows], point))])


def _distances(corners: np.ndarray, point: np.ndarray) -> np.ndarray:
    """Distances (T,) from a point to triangles (T, 3, 3)."""
    q = closest_points_on_triangles(np.repeat(point[None], len(corners), axis=0),
                                    corners[:, 0], corners[:, 1], corners[:, 2])
    return np.linalg.norm(q - point, axis=1)


def face_of(faces: np.ndarray, point: SurfacePoint) -> int:
    """The row of `faces` that a surface point lies on; −1 if none has its corners (a
    subdivided copy of the body: the point's face was split)."""
    a, b, c = point.corners
    rows = np.flatnonzero(faces[:, 0] == a)
    rows = rows[(faces[rows, 1] == b) & (faces[rows, 2] == c)]
    return int(rows[0]) if len(rows) else -1


def insert_points(vertices: np.ndarray, faces: np.ndarray, points: np.ndarray,
                  on_faces: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The surface with each point (P, 3) made a vertex: its nearest face split in three.

    Returns the new vertices (the old ones first), faces (the unsplit ones in their order,
    then the new ones), and the vertex index (P,) of each point. A point on a vertex (within
    round-off) is that vertex. The nearest face is searched among the original faces (unless
    `on_faces` (P,) gives it: a row of `faces`, or −1 to search), then among the pieces that
    earlier points split it into.
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    hints = np.full(len(points), -1) if on_faces is None else np.asarray(on_faces)
    search = FaceSearch(vertices[faces]) if (hints < 0).any() else None
    table = np.concatenate([faces, np.zeros((3 * len(points), 3), dtype=np.int64)])
    alive = np.zeros(len(table), dtype=bool)
    alive[:len(faces)] = True
    pieces: dict[int, list[int]] = {}  # a split face → the faces it was split into
    pool, rows_used, indices = vertices, len(faces), []
    for point, hint in zip(points, hints):
        leaves, stack = [], [int(hint) if hint >= 0 or search is None else search.nearest(point)]
        while stack:
            row = stack.pop()
            leaves.append(row) if alive[row] else stack.extend(pieces[row])
        face = leaves[int(np.argmin(_distances(pool[table[leaves]], point)))]
        weights = barycentric(pool[table[face]], point)
        if weights.max() > 1.0 - 1e-9:
            indices.append(int(table[face, np.argmax(weights)]))
            continue
        weights = np.maximum(weights, _INSIDE)
        weights /= weights.sum()
        a, b, c = table[face]
        new = len(pool)
        pool = np.concatenate([pool, (weights @ pool[table[face]])[None]])
        table[rows_used:rows_used + 3] = [[a, b, new], [b, c, new], [c, a, new]]
        alive[face], alive[rows_used:rows_used + 3] = False, True
        pieces[face] = [rows_used, rows_used + 1, rows_used + 2]
        rows_used += 3
        indices.append(new)
    return pool, table[alive], np.array(indices, dtype=np.int64)
