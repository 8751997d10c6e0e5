"""Tissue materials from a TOML file: one table per tissue region, checked on load.

Two presets ship: `data/materials.toml`, the literature's values with their
sources, the default and where the identification starts, and
`data/materials_calibrated.toml`, identified from the validation set's
measurements of living people by `hitogata identify`. A user file has the
same form. Every mistake (a missing or unknown region or key, a
value out of range) is a one-line `HitogataError` naming the file, the entry
and the value.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from types import MappingProxyType
from typing import Any, Mapping

from hitogata import units
from hitogata.errors import HitogataError
from hitogata.fem import Material
from hitogata.config import Entry, read_toml
from hitogata.options import DEFAULT_MATERIALS, MaterialsPreset
from hitogata.volume import REGIONS

# The shipped presets' files (`options.MATERIALS_PRESETS`): the literature's values, and those identified from
# the validation set's in-vivo stiffness rows by `hitogata identify` (docs/decisions/0023-calibrated-materials.md);
# which is the default: `options.DEFAULT_MATERIALS`.
PRESET_FILES: dict[MaterialsPreset, str] = {"literature": "materials.toml", "calibrated": "materials_calibrated.toml"}
KEYS = ("density", "youngs_modulus", "poissons_ratio")
DAMPING_KEYS = ("alpha", "beta")
PRESSURE_UNITS = {"pa": 1.0, "kpa": 1e3, "mpa": 1e6, "gpa": 1e9}  # parse_quantity lower-cases the unit


@dataclass(frozen=True)
class Materials:
    """A checked material per tissue region (names as in `hitogata.volume.REGIONS`)."""

    source: str
    regions: Mapping[str, Material]
    rayleigh: tuple[float, float] | None = None  # (alpha 1/s, beta s) from the file's [damping], if it has one

    def table(self, region_names: tuple[str, ...]) -> dict[int, Material]:
        """Region index -> Material, for `hitogata.fem.region_materials`."""
        return {k: self.regions[name] for k, name in enumerate(region_names)}


def default_materials_path() -> Path:
    """The shipped materials file every elastic body is built with unless told otherwise."""
    return shipped_materials()[DEFAULT_MATERIALS]


def shipped_materials() -> dict[str, Path]:
    """The shipped presets' files by name."""
    return {name: Path(str(resources.files("hitogata").joinpath("data", file))) for name, file in PRESET_FILES.items()}


def materials_name(materials: Materials | None) -> str:
    """How a file or the metadata names the materials used: a shipped preset's name, else the file's path."""
    return DEFAULT_MATERIALS if materials is None else source_name(materials.source)


def source_name(source: str | Path) -> str:
    """A materials file by a shipped preset's name where it is one, else its path as given."""
    shipped = {str(path): name for name, path in shipped_materials().items()}
    return shipped.get(str(source), str(source))


def load_materials(path: str | Path | None = None) -> Materials:
    """Read and check a materials file, or a shipped preset by name (`MATERIALS_PRESETS`; `DEFAULT_MATERIALS` when
    None)."""
    if path is None or str(path) in PRESET_FILES:
        path = shipped_materials()[DEFAULT_MATERIALS if path is None else str(path)]
    source, doc = read_toml(path)
    unknown = sorted(set(doc) - set(REGIONS) - {"damping"})
    if unknown:
        raise HitogataError(f"{source}: [{unknown[0]}]: unknown region; allowed: {', '.join(REGIONS)} (and [damping])")
    missing = [name for name in REGIONS if name not in doc]
    if missing:
        raise HitogataError(f"{source}: no [{missing[0]}] table; every region needs one: {', '.join(REGIONS)}")
    regions = {name: _material(Entry(source, f"[{name}]", doc[name], KEYS), name) for name in REGIONS}
    rayleigh = _damping(Entry(source, "[damping]", doc["damping"], DAMPING_KEYS)) if "damping" in doc else None
    return Materials(source, MappingProxyType(regions), rayleigh)


def _damping(entry: Entry) -> tuple[float, float]:
    """Rayleigh damping C = alpha M + beta K of the soft tissue: alpha (1/s) and beta (s), both >= 0."""
    alpha = _checked(entry, "alpha", entry.number("alpha"), lambda v: v >= 0, ">= 0 (1/s)")
    beta = _checked(entry, "beta", entry.number("beta"), lambda v: v >= 0, ">= 0 (s)")
    return alpha, beta


def _material(entry: Entry, name: str) -> Material:
    for key in KEYS:
        entry.get(key, (float, str) if key == "youngs_modulus" else float)  # presence and type
    rho = _checked(entry, "density", entry.number("density"), lambda v: v > 0, "> 0 kg/m^3")
    E = _checked(entry, "youngs_modulus", _pressure(entry, entry.table["youngs_modulus"]), lambda v: v > 0, "> 0 Pa")
    nu = _checked(entry, "poissons_ratio", entry.number("poissons_ratio"), lambda v: 0 <= v < 0.5, "0 <= nu < 0.5")
    return Material(E=E, nu=nu, rho=rho, name=name)


def _pressure(entry: Entry, value: Any) -> float:
    """Pa from a number (Pa) or a string with a unit ("25kPa")."""
    if isinstance(value, str):
        try:
            return units.parse_quantity(value, PRESSURE_UNITS, "youngs_modulus")
        except HitogataError:
            entry.fail(f"youngs_modulus = {value!r}: write Pa as a number, or a number with a unit "
                       "(Pa, kPa, MPa, GPa), e.g. \"25kPa\"")
    return float(value)


def _checked(entry: Entry, key: str, value: float, ok, allowed: str) -> float:
    if not (math.isfinite(value) and ok(value)):
        entry.fail(f"{key} = {entry.table[key]!r} is invalid; allowed: {allowed}")
    return float(value)
