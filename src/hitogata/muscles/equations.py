"""The paper's two muscle equations and their inverses, vectorised.

Eq. 1 (flexion): bones ab and ac meet at the joint a; the muscle joins d on ab
to e on ac, |ad| = d1, |ae| = d2, |de| = l. The law of cosines gives the joint
angle θ = arccos((d1² + d2² − l²) / (2 d1 d2)), defined for
|d1 − d2| ≤ l ≤ d1 + d2 (θ from 0 to π).

Eq. 2 (axial rotation): the muscle winds as a helix round a cylindrical bone of
radius r over a height d; unrolled it is the hypotenuse of a right triangle
with legs d and rφ, so φ = sqrt(l² − d²) / r, defined for l ≥ d (φ ≥ 0).

Outside its domain each function either raises a one-line `HitogataError` or,
with `clamp=True`, clamps the length onto the domain's edge; never NaN.
"""

from __future__ import annotations

import numpy as np

from hitogata.errors import HitogataError

ROUNDING = 1e-12  # relative: lengths this close outside the domain are on its edge


def flexion_domain(d1: np.ndarray, d2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Shortest and longest muscle lengths eq. 1 allows: |d1 − d2| and d1 + d2."""
    d1, d2 = np.asarray(d1, dtype=float), np.asarray(d2, dtype=float)
    return np.abs(d1 - d2), d1 + d2


def _onto(values: np.ndarray, lo: np.ndarray | float, hi: np.ndarray | float, clamp: bool, what: str) -> np.ndarray:
    """Values clipped onto [lo, hi]; outside by more than rounding is an error unless clamping."""
    lo, hi = np.broadcast_to(lo, values.shape), np.broadcast_to(hi, values.shape)
    if not np.all(np.isfinite(values)):
        raise HitogataError(f"{what}: got a value that is not a finite number")
    scale = np.maximum(np.where(np.isfinite(hi), np.abs(hi), np.abs(lo)), 1.0)
    outside = (values < lo - ROUNDING * scale) | (values > hi + ROUNDING * scale)
    if outside.any() and not clamp:
        k = np.unravel_index(np.argmax(outside), outside.shape)
        raise HitogataError(
            f"{what} {float(values[k]):.6g} m is outside the domain [{float(lo[k]):.6g}, {float(hi[k]):.6g}] m"
        )
    return np.clip(values, lo, hi)


def flexion_angle(d1: np.ndarray, d2: np.ndarray, length: np.ndarray, clamp: bool = False) -> np.ndarray:
    """Eq. 1: joint angle θ (rad, 0…π) from the muscle length l and distances d1, d2."""
    d1, d2 = np.asarray(d1, dtype=float), np.asarray(d2, dtype=float)
    if np.any(d1 <= 0) or np.any(d2 <= 0):
        raise HitogataError("eq. 1 needs d1 > 0 and d2 > 0 (attachments off the joint centre)")
    lo, hi = flexion_domain(d1, d2)
    ll = _onto(np.asarray(length, dtype=float), lo, hi, clamp, "eq. 1: muscle length")
    cosine = (d1 * d1 + d2 * d2 - ll * ll) / (2.0 * d1 * d2)
    return np.arccos(np.clip(cosine, -1.0, 1.0))


def flexion_length(d1: np.ndarray, d2: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """Inverse of eq. 1: the muscle length for a joint angle θ (rad)."""
    d1, d2, theta = (np.asarray(v, dtype=float) for v in (d1, d2, theta))
    return np.sqrt(np.maximum(d1 * d1 + d2 * d2 - 2.0 * d1 * d2 * np.cos(theta), 0.0))


def rotation_angle(length: np.ndarray, height: np.ndarray, radius: np.ndarray, clamp: bool = False) -> np.ndarray:
    """Eq. 2: twist φ (rad, ≥ 0) of the cylinder from the helix length l, height d, radius r."""
    d, r = np.asarray(height, dtype=float), np.asarray(radius, dtype=float)
    if np.any(r <= 0) or np.any(d < 0):
        raise HitogataError("eq. 2 needs a radius r > 0 and a height d >= 0")
    ll = _onto(np.asarray(length, dtype=float), d, np.inf, clamp, "eq. 2: helix length")
    return np.sqrt(np.maximum(ll * ll - d * d, 0.0)) / r


def rotation_length(phi: np.ndarray, height: np.ndarray, radius: np.ndarray) -> np.ndarray:
    """Inverse of eq. 2: the helix length for a twist φ ≥ 0 (rad)."""
    phi, d, r = (np.asarray(v, dtype=float) for v in (phi, height, radius))
    return np.hypot(d, r * phi)
