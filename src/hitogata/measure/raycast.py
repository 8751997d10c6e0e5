"""First hit of a ray with a triangle mesh (Möller–Trumbore, vectorised over faces)."""

from __future__ import annotations

import numpy as np


def first_hit(
    vertices: np.ndarray, faces: np.ndarray, origin: np.ndarray, direction: np.ndarray
) -> tuple[int, np.ndarray]:
    """Index of the first face the ray crosses and the crossing point; (-1, nan) if none."""
    direction = np.asarray(direction, dtype=np.float64) / np.linalg.norm(direction)
    tri = vertices[faces]
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    p = np.cross(direction, e2)
    det = np.einsum("ij,ij->i", e1, p)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / det
        s = origin - tri[:, 0]
        u = np.einsum("ij,ij->i", s, p) * inv
        q = np.cross(s, e1)
        v = (q @ direction) * inv
        t = np.einsum("ij,ij->i", e2, q) * inv
    hit = (np.abs(det) > 1e-15) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
    if not hit.any():
        return -1, np.full(3, np.nan)
    face = int(np.flatnonzero(hit)[np.argmin(t[hit])])
    return face, origin + t[face] * direction


def nearest_corner(vertices: np.ndarray, faces: np.ndarray, face: int, point: np.ndarray) -> int:
    """The vertex of `face` closest to `point`."""
    corners = faces[face]
    return int(corners[np.argmin(np.linalg.norm(vertices[corners] - point, axis=1))])
