"""Skin strain between the rest surface and a posed or deformed one (same topology): per triangle,
the principal stretches, the area ratio and the direction of the largest stretch at rest
(`geometry.strain` computes them), and the stretch along a direction drawn on the skin.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.geometry.strain import deformation, principal_stretches


@dataclass(frozen=True)
class SkinStrain:
    """Per-triangle principal stretches (F,), area ratio (F,), the λ1 direction at rest (F, 3)."""

    stretch_max: np.ndarray
    stretch_min: np.ndarray
    area_ratio: np.ndarray
    direction: np.ndarray
    rest_area: np.ndarray

    @property
    def strain_max_percent(self) -> np.ndarray:
        """Largest principal (engineering) strain, %: (λ1 − 1) × 100."""
        return (self.stretch_max - 1.0) * 100.0


def skin_strain(rest: np.ndarray, deformed: np.ndarray, faces: np.ndarray) -> SkinStrain:
    """Principal stretches of every triangle from `rest` to `deformed` (both (V, 3), metres).

    A triangle of zero rest area has no defined strain: its values are NaN.
    """
    stretch_max, stretch_min, area_ratio, direction, area = principal_stretches(rest, deformed, faces)
    return SkinStrain(
        stretch_max=stretch_max,
        stretch_min=stretch_min,
        area_ratio=area_ratio,
        direction=direction,
        rest_area=area,
    )


def directional_stretch(rest: np.ndarray, deformed: np.ndarray, faces: np.ndarray, directions: np.ndarray
                        ) -> np.ndarray:
    """Stretch (F,) of each triangle along a direction given at rest (F, 3): the length a short line
    of skin drawn that way has now over its rest length (what marks on the skin, a tape between two
    dots, measure). The direction is projected into the triangle's rest plane first; a direction
    normal to the triangle, or a triangle of zero area, gives NaN."""
    a, c, d, t, b, _ = deformation(rest, deformed, faces)
    u, w = np.einsum("ij,ij->i", directions, t), np.einsum("ij,ij->i", directions, b)
    with np.errstate(invalid="ignore", divide="ignore"):
        norm = np.hypot(u, w)
        u, w = u / norm, w / norm
        return np.hypot(a * u + c * w, d * w)
