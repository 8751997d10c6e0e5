"""First hit of a ray with the skin."""

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
