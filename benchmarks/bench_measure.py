"""Measurement benchmark: time to take all ISO 8559-1 measurements of one body.

Goal (issue 6, and the made-to-measure issue): all measurements of one body ≤ 200 ms (landmarks are found
once per body and cached; that search is timed separately).
Baseline, measured in the same run: the same measurements with a naive section
(a Python loop over the triangles, loops joined with a dictionary walk) and one
geodesic solver built per leg of a surface path instead of one per posture. Both must
agree to 1e-9 m, so the speed-up compares equal work.
"""

from __future__ import annotations

import statistics

import numpy as np
from scipy.spatial import ConvexHull

from timing import timed

from hitogata.body.assets import load_assets
from hitogata.body import default_body
from hitogata.measure.axes import JointSet
from hitogata.measure.geodesic import SurfaceGeodesics
from hitogata.measure.landmarks import body_landmarks, find_landmarks, girdle_point, reference_vertices
from hitogata.measure.measurements import (
    MEASUREMENT_NAMES,
    SURFACE_ENDS,
    SURFACE_ROUTES,
    girth_planes,
    heights,
    measure,
)
from hitogata.measure.measurements import tapes as measure_tapes
from hitogata.measure.sections import plane_basis
from hitogata.measure.surface_points import insert_points



def naive_girth(vertices: np.ndarray, faces: np.ndarray, origin, normal, centre) -> float:
    """One girth the slow way: visit every triangle in Python, walk the loops, hull the one round the centre."""
    n, u, v = plane_basis(normal)
    centre = centre - ((centre - origin) @ n) * n
    d = (vertices - origin) @ n
    neighbours: dict[tuple[int, int], list[tuple[int, int]]] = {}
    points: dict[tuple[int, int], np.ndarray] = {}
    for tri in faces.tolist():
        cut = []
        for a, b in ((tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])):
            if (d[a] >= 0) != (d[b] >= 0):
                key = (min(a, b), max(a, b))
                t = d[key[0]] / (d[key[0]] - d[key[1]])
                points[key] = vertices[key[0]] + t * (vertices[key[1]] - vertices[key[0]])
                cut.append(key)
        if len(cut) == 2:
            neighbours.setdefault(cut[0], []).append(cut[1])
            neighbours.setdefault(cut[1], []).append(cut[0])
    seen: set = set()
    chosen = []
    for start in points:
        if start in seen:
            continue
        loop, stack = [], [start]
        while stack:
            key = stack.pop()
            if key in seen:
                continue
            seen.add(key)
            loop.append(key)
            stack.extend(neighbours.get(key, []))
        flat = np.array([[(points[k] - centre) @ u, (points[k] - centre) @ v] for k in loop])
        hull = ConvexHull(flat)
        if np.all(hull.equations[:, :2] @ np.zeros(2) + hull.equations[:, 2] <= 0):
            chosen.append(np.array([points[k] for k in loop]))
    pts = np.vstack(chosen)
    flat = np.stack([pts @ u, pts @ v], axis=1)
    ring = flat[ConvexHull(flat).vertices]
    return float(np.linalg.norm(np.diff(np.vstack([ring, ring[:1]]), axis=0), axis=1).sum())


def naive_measure(body) -> dict[str, float]:
    """All measurements with naive sections and a geodesic solver per leg (the armscye's tape,
    cut below the axilla, the across widths' and the crotch length's arcs as `measure` takes them)."""
    v, f, marks = body.vertices, body.faces, body_landmarks(body)
    joints = JointSet(body.rig.names, body.rig.heads)
    values = heights(v, marks)
    ends = {"acromion_right": girdle_point(marks, joints, joints, "R"),
            "acromion_left": girdle_point(marks, joints, joints, "L")}
    ends.update({name: getattr(marks, name).at(v) for name in SURFACE_ENDS})
    v_pts, f_pts, indices = insert_points(v, f, np.stack(list(ends.values())))
    at = dict(zip(ends, indices.tolist()))
    for name, route in SURFACE_ROUTES.items():
        values[name] = sum(SurfaceGeodesics(v_pts, f_pts).length(at[a], at[b]) for a, b in zip(route, route[1:]))
    for name, plane in girth_planes(v, marks, joints, joints).items():
        values[name] = naive_girth(v, f, *plane)
    tapes = measure_tapes(v, f, marks, joints, joints)
    values.update({name: tapes[name].girth for name in ("armscye_girth", "crotch_length", "across_back_width",
                                                        "across_front_width")})
    return values


def main() -> None:
    load_assets()  # the shipped data's load is benchmarked in bench_body.py
    reference_vertices.cache_clear()
    once = timed(reference_vertices, 1)[0]
    print(f"nipple and navel vertices on the reference shape, once per process: {1e3 * once:.0f} ms")
    for sex in ("female", "male"):
        body = default_body(sex)
        joints = JointSet(body.rig.names, body.rig.heads)
        first = statistics.median(timed(lambda body=body, joints=joints: find_landmarks(body.vertices, body.faces, joints), 3))
        measure(body)  # warm caches (topology, this body's landmarks)
        fast = statistics.median(timed(lambda body=body: measure(body), 7))
        slow = statistics.median(timed(lambda body=body: naive_measure(body), 2))
        ours, naive = measure(body).as_dict(), naive_measure(body)
        worst = max(abs(ours[n] - naive[n]) for n in MEASUREMENT_NAMES)
        print(
            f"{sex}: all {len(MEASUREMENT_NAMES)} measurements median {1e3 * fast:.0f} ms (goal ≤ 200 ms); "
            f"landmarks, once per body: {1e3 * first:.0f} ms"
        )
        print(
            f"  baseline (Python-loop sections, a geodesic solver per path): {1e3 * slow:.0f} ms; "
            f"speed-up {slow / fast:.1f}×; largest difference {worst * 1e3:.1e} mm"
        )


if __name__ == "__main__":
    main()
