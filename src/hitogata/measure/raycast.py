"""First hit of a ray with the skin, and the nearest corner of a hit face."""

from __future__ import annotations

import numpy as np

from hitogata.geometry.raycast import ray_triangle


def first_hit(
    vertices: np.ndarray, faces: np.ndarray, origin: np.ndarray, direction: np.ndarray
) -> tuple[int, np.ndarray]:
    """Index of the first face the ray crosses and the crossing point; (-1, nan) if none."""
    direction = np.asarray(direction, dtype=np.float64) / np.linalg.norm(direction)
    t = ray_triangle(origin, direction, vertices[faces], t_min=np.finfo(float).tiny)
    if not np.isfinite(t).any():
        return -1, np.full(3, np.nan)
    face = int(np.argmin(t))
    return face, origin + t[face] * direction


def nearest_corner(vertices: np.ndarray, faces: np.ndarray, face: int, point: np.ndarray) -> int:
    """The vertex of `face` closest to `point`."""
    corners = faces[face]
    return int(corners[np.argmin(np.linalg.norm(vertices[corners] - point, axis=1))])
