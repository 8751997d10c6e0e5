"""Small rotation kernels, batched: quaternions to matrices, products, and rotation extraction.

`extract_rotations` finds the rotation R maximising tr(Rᵀ F) for many 3x3
matrices F at once by the iteration of Müller et al. 2016 ("A robust
method to extract the rotational part of deformations"): each step turns R
towards F by the axis-angle Σ rᵢ × fᵢ / |Σ rᵢ · fᵢ| (columns). Warm-started
from the previous solve it needs a few cheap steps where an SVD per matrix
costs ~20x more, and it always returns a proper rotation, also for an
inverted F (where it is the SVD's rotation with the smallest direction flipped).
"""

from __future__ import annotations

import numpy as np

STEPS = 4  # extraction steps per call (warm-started)


def quaternion_matrices(q: np.ndarray) -> np.ndarray:
    """Rotation matrices (..., 3, 3) of unit quaternions (..., 4) as (w, x, y, z)."""
    w, x, y, z = np.moveaxis(q, -1, 0)
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=-1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1),
    ], axis=-2)


def quaternion_product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton products a ⊗ b of quaternions (..., 4)."""
    aw, ax, ay, az = np.moveaxis(a, -1, 0)
    bw, bx, by, bz = np.moveaxis(b, -1, 0)
    return np.stack([
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    ], axis=-1)


def extract_rotations(F: np.ndarray, start: np.ndarray, steps: int = STEPS) -> tuple[np.ndarray, np.ndarray]:
    """Rotations (M, 3, 3) nearest to F (M, 3, 3) and their quaternions (M, 4), from start quaternions (M, 4)."""
    q = start
    for _ in range(steps):
        R = quaternion_matrices(q)
        turn = np.cross(R, F, axis=1).sum(axis=2)  # Σ_i r_i × f_i over the columns i
        along = np.abs(np.einsum("mij,mij->m", R, F)) + 1e-9
        omega = turn / along[:, None]
        angle = np.linalg.norm(omega, axis=1)
        half = 0.5 * angle
        axis = omega / np.maximum(angle, 1e-300)[:, None]
        dq = np.concatenate([np.cos(half)[:, None], np.sin(half)[:, None] * axis], axis=1)
        q = quaternion_product(dq, q)
        q /= np.linalg.norm(q, axis=1, keepdims=True)
    return quaternion_matrices(q), q
