"""Where rays or segments meet triangles (Möller–Trumbore 1997, vectorised over triangles)."""

from __future__ import annotations

import numpy as np

PARALLEL = 1e-15  # |det| below this: the ray runs in the triangle's plane and is taken as missing it


def ray_triangle(
    origin: np.ndarray, direction: np.ndarray, triangles: np.ndarray, t_min: float = 0.0, t_max: float = np.inf
) -> np.ndarray:
    """Parameter t at which origin + t·direction meets each triangle, inf where it misses.

    origin and direction are (3,) or one row per triangle (F, 3); triangles (F, 3, 3).
    Only t_min ≤ t ≤ t_max counts (a segment start→end is origin=start,
    direction=end−start, t in [0, 1]).
    """
    e1, e2 = triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0]
    p = np.cross(direction, e2)
    det = np.einsum("ij,ij->i", e1, p)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / det
        s = origin - triangles[:, 0]
        u = np.einsum("ij,ij->i", s, p) * inv
        q = np.cross(s, e1)
        v = np.einsum("ij,ij->i", np.broadcast_to(direction, q.shape), q) * inv
        t = np.einsum("ij,ij->i", e2, q) * inv
        hit = (np.abs(det) > PARALLEL) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t >= t_min) & (t <= t_max)
    return np.where(hit, t, np.inf)
