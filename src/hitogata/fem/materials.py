"""Isotropic linear-elastic materials, one per tissue region, spread to elements.

A mesh labels each tet with an integer region; a table maps regions to
(E, nu, rho). Validation lives here so every assembler refuses the same bad
values with the same one-line message.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from hitogata.errors import HitogataError


@dataclass(frozen=True)
class Material:
    """Young's modulus E (Pa), Poisson's ratio nu (-), density rho (kg/m^3)."""

    E: float
    nu: float
    rho: float
    name: str = ""

    def __post_init__(self) -> None:
        check_material(self.E, self.nu, self.rho, where=self.name or "material")


def check_material(E: float | np.ndarray, nu: float | np.ndarray, rho: float | np.ndarray | None = None,
                   where: str = "material") -> None:
    """Raise HitogataError unless E > 0, 0 <= nu < 0.5 and rho > 0 (all finite)."""
    for label, value, ok, allowed in (
        ("E", E, lambda v: v > 0, "> 0 Pa"),
        ("nu", nu, lambda v: (v >= 0) & (v < 0.5), "0 <= nu < 0.5"),
        ("rho", rho, lambda v: v > 0, "> 0 kg/m^3"),
    ):
        if value is None:
            continue
        v = np.asarray(value, dtype=float).ravel()
        bad = ~(np.isfinite(v) & ok(v))
        if np.any(bad):
            i = int(np.argmax(bad))
            which = f" (element {i})" if v.size > 1 else ""
            raise HitogataError(f"{where}: {label} = {float(v[i])!r}{which} is invalid; allowed: {allowed}")


def lame(E: np.ndarray | float, nu: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
    """Lame parameters (lambda, mu) from E and nu."""
    E = np.asarray(E, dtype=float)
    nu = np.asarray(nu, dtype=float)
    return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))


def per_element(n_elements: int, value: float | np.ndarray, name: str) -> np.ndarray:
    """Broadcast a scalar or (T,) array of a material property to one value per element."""
    v = np.asarray(value, dtype=float)
    if v.ndim == 0:
        return np.full(n_elements, float(v))
    if v.shape != (n_elements,):
        raise HitogataError(f"{name} has shape {v.shape}; allowed: a scalar or one value per element ({n_elements},)")
    return v


def per_sample(n_elements: int, n_samples: int, value: float | np.ndarray, name: str) -> np.ndarray:
    """A material property as (T, 1), uniform in each element (from a scalar or (T,)), or as
    (T, Q), one value per material sample point of each element (`elements.MATERIAL_SAMPLES`)."""
    v = np.asarray(value, dtype=float)
    if v.shape == (n_elements, n_samples):
        return v
    if v.ndim == 2:
        raise HitogataError(f"{name} has shape {v.shape}; allowed: a scalar, one value per element "
                            f"({n_elements},) or per material sample point ({n_elements}, {n_samples})")
    return per_element(n_elements, v, name)[:, None]


def region_materials(regions: np.ndarray, table: Mapping[int, Material]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(E, nu, rho) arrays of the shape of `regions` (region labels per element (T,), or per
    material sample point (T, Q)) from a region -> Material table."""
    regions = np.asarray(regions)
    missing = sorted(set(np.unique(regions).tolist()) - set(table))
    if missing:
        raise HitogataError(f"region {missing[0]} has no material; allowed regions: {sorted(table)}")
    keys = np.array(sorted(table))
    props = np.array([[table[k].E, table[k].nu, table[k].rho] for k in keys])
    rows = props[np.searchsorted(keys, regions)]
    return rows[..., 0].copy(), rows[..., 1].copy(), rows[..., 2].copy()
