"""Garment files (TOML): a tubular garment along a body segment, its relaxed size and its fabric.

    title = "Legging"
    segment = "leg"                      # leg (right), arm (right) or trunk
    ease = "-20%"                        # against the standing body's girth at every station, or
    # [relaxed]                          # the relaxed circumference at levels (interpolated between them)
    # ankle = "14.1cm"                   # or
    # mesh = "legging_mesh.obj"          # its mesh in the rest shape (OBJ or PLY, relative to this file;
    # mesh_unit = "m"                    # `garment_mesh`), in m, cm or mm
    levels = ["ankle", "calf", "knee", "thigh"]   # the levels it covers, in order (default: the segment's)
    [fabric]
    course = "400N/m"                    # a linear fabric's modulus, or a tensile test's CSV (`read_fabric_csv`)
    wale = "200N/m"                      # the same along the wale (default: the course's)
    shear = "30N/m"                      # shear stiffness per radian (default 30 N/m)

Read and checked in one place: every mistake is one line naming the file, the
entry, the value and what is allowed. Shipped examples are usable by name
(`shipped_garments`). docs/garment_contact.md documents the format.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

from hitogata import units
from hitogata.config import Entry, read_toml
from hitogata.errors import HitogataError
from hitogata.garment.contact.garment_mesh import MESH_UNITS, GarmentMesh, read_garment_mesh
from hitogata.garment.fabric import Fabric, read_fabric_csv

# the levels of each segment in order along it (the measured girths'; right side for a limb)
SEGMENTS: dict[str, tuple[str, ...]] = {
    "leg": ("ankle", "calf", "knee", "thigh"),
    "arm": ("wrist", "elbow", "upper_arm"),
    "trunk": ("hip", "waist", "underbust", "chest"),
}
MODULUS_UNITS = {"n/m": 1.0, "n/cm": 100.0, "n/mm": 1000.0}
SHEAR = 30.0  # N/m per radian: a knit's shear stiffness, Kawabata's G ≈ 0.5 gf/(cm·deg) (KES-FB1)
PER_RING = 64  # vertices round each ring


@dataclass(frozen=True)
class GarmentSpec:
    """One garment file, checked, in SI: its segment, the levels it covers, its relaxed circumferences (m,
    by level), one ease or its rest mesh, the fabric's course and wale curves and shear stiffness (N/m)."""

    source: str
    title: str
    segment: str
    levels: tuple[str, ...]
    relaxed: dict[str, float] | None
    ease: float | None
    course: Fabric
    wale: Fabric
    shear: float = SHEAR
    per_ring: int = PER_RING
    mesh: GarmentMesh | None = None

    def where(self, level: str) -> str:
        """The entry that sets a level's relaxed size, for messages."""
        if self.mesh is not None:
            return f"{self.source}: mesh"
        return f"{self.source}: relaxed.{level}" if self.relaxed is not None else f"{self.source}: ease"


def shipped_garments() -> dict[str, Path]:
    """The example garments shipped with the package, by name."""
    folder = resources.files("hitogata") / "data" / "garments"
    return {p.name.removesuffix(".toml"): Path(str(p)) for p in folder.iterdir() if p.name.endswith(".toml")}


def garment_file(name: str) -> Path:
    """A shipped garment's file by name, or the file itself; one line if neither."""
    shipped = shipped_garments()
    if name in shipped:
        return shipped[name]
    path = Path(name)
    if not path.is_file():
        raise HitogataError(f"garment {name!r}: no such file; allowed a garment file or a shipped garment: "
                            f"{', '.join(sorted(shipped))}")
    return path


def load_garment(name: str | Path) -> GarmentSpec:
    """Read and check a garment file (or a shipped garment by name)."""
    path = garment_file(str(name))
    source, data = read_toml(path)
    return parse_garment(data, source, path.parent)


def parse_garment(data: dict[str, Any], source: str, folder: Path) -> GarmentSpec:
    """Check a parsed garment document; fabric CSVs are read relative to `folder`."""
    top = Entry(source, "file", data, ("title", "segment", "levels", "ease", "relaxed", "mesh", "mesh_unit", "fabric",
                                       "per_ring"))
    title = top.get("title", str, Path(source).stem)
    segment = top.choice("segment", tuple(SEGMENTS), "leg")
    allowed = SEGMENTS[segment]
    if sum(key in data for key in ("ease", "relaxed", "mesh")) != 1:
        top.fail("give one of `ease`, a [relaxed] table of circumferences by level or a `mesh` file")
    if "mesh_unit" in data and "mesh" not in data:
        top.fail("`mesh_unit` without a `mesh`; allowed with a mesh file only", "mesh_unit")
    relaxed: dict[str, float] | None = None
    ease = None
    mesh = None
    if "mesh" in data:
        unit = MESH_UNITS[top.choice("mesh_unit", tuple(MESH_UNITS), "m")]
        mesh = read_garment_mesh(folder / top.get("mesh", str), f"{source}: mesh", unit)
        levels = allowed
    elif "relaxed" in data:
        table = Entry(source, "relaxed", data["relaxed"], allowed)
        relaxed = {}
        for level in allowed:
            value = table.quantity(level, units.LENGTH_UNITS, None, 0.0, 3.0, "a circumference > 0 and up to 3 m, like 14.1cm")
            if value is not None:
                if not value > 0:
                    table.fail(f"{data['relaxed'][level]!r}; allowed a circumference > 0, like 14.1cm", level)
                relaxed[level] = value
        if len(relaxed) < 1:
            table.fail(f"no level; allowed one or more of {', '.join(allowed)}")
        levels = tuple(level for level in allowed if level in relaxed)
    else:
        ease = top.quantity("ease", units.FRACTION_UNITS, 0.0, -0.6, 0.5, "an ease from -60% to 50%, like -20%")
        levels = allowed
    if "levels" in data:
        named = top.names("levels")
        for level in named:
            if level not in allowed:
                top.fail(f"{level!r}; allowed levels of the {segment}: {', '.join(allowed)}", "levels")
        if relaxed is not None and set(named) != set(relaxed):
            top.fail(f"{list(named)!r}; allowed the levels of [relaxed] ({', '.join(relaxed)})", "levels")
        levels = tuple(level for level in allowed if level in named)
    if len(levels) < 2 and relaxed is None:
        top.fail(f"{list(levels)!r}; allowed two or more levels (a tube between them)", "levels")
    per_ring = top.integer("per_ring", PER_RING, 16, 256)
    fabric = Entry(source, "fabric", data.get("fabric", {}), ("course", "wale", "shear"))
    course = _fabric(fabric, "course", folder, None)
    wale = _fabric(fabric, "wale", folder, course)
    shear = fabric.quantity("shear", MODULUS_UNITS, SHEAR, 0.0, 1e5, "a shear stiffness ≥ 0 like 30N/m")
    return GarmentSpec(source, title, segment, levels, relaxed, ease, course, wale, shear, per_ring, mesh)


def _fabric(entry: Entry, key: str, folder: Path, default: Fabric | None) -> Fabric:
    """A direction's fabric: a modulus like "400N/m" or a tensile test's CSV file (relative to the garment's)."""
    if key not in entry.table:
        if default is None:
            entry.fail(f"missing key {key!r}; allowed a modulus like \"400N/m\" or a tensile test's CSV file")
        return default
    value = entry.table[key]
    if isinstance(value, str) and value.strip().lower().endswith(".csv"):
        return read_fabric_csv(folder / value)
    modulus = entry.quantity(key, MODULUS_UNITS, math.nan, 1e-3, 1e6,
                             "a modulus > 0 like 400N/m (tension per unit strain) or a CSV file")
    return Fabric.linear(modulus)
