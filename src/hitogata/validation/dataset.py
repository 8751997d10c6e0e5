"""The validation set: published measurements of living people, read and checked.

A TOML file of `[[source]]` tables (one per publication: who was measured,
how) and `[[row]]` tables (one figure: kind, quantity, posture, mean, spread,
unit, where in the paper). The schema is `data/validation/SCHEMA.md`; the
shipped set is `data/validation/measured_people.toml`. Every mistake is one
line naming the file, the row, the value and what is allowed.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from types import MappingProxyType
from typing import Any

from hitogata.config import Entry, read_toml
from hitogata.errors import HitogataError
from hitogata.garment.levels import LEVELS
from hitogata.measure.values import MEASUREMENT_NAMES

SHIPPED_FILE = "measured_people.toml"

KINDS = ("posture_change", "skin_strain", "frequency", "damping", "stiffness", "pressure")
UNITS: Mapping[str, tuple[str, ...]] = MappingProxyType({
    "posture_change": ("cm", "%"),
    "skin_strain": ("%",),
    "frequency": ("Hz",),
    "damping": ("1", "1/s"),
    "stiffness": ("kPa",),
    "pressure": ("mmHg",),
})
SKIN_ZONES = ("back", "lower_back", "seat", "elbow", "knee", "shoulder")
SKIN_DIRECTIONS = ("vertical", "horizontal", "area")
SOFT_TISSUE_REGIONS = ("thigh", "calf", "shin", "upper_arm", "forearm", "abdomen", "breast")
TISSUES = ("muscle", "fat", "skin")
MODULI = ("shear_modulus", "youngs_modulus")
SD_OF = ("change", "values", "range", "guessed")
RESONANT = ("frequency", "damping")
# how a frequency or damping row's oscillation was set off, where not by an impact on the segment's skeleton:
# "myometer", a hand-held probe's brief tap ringing the tissue under it (MyotonPRO and the like)
PROBES = ("myometer",)
SEXES = ("female", "male", "mixed")
POSTURED = ("posture_change", "skin_strain", "pressure")

SOURCE_KEYS = ("id", "authors", "year", "title", "journal", "doi", "url", "method", "n", "subjects")
SUBJECT_KEYS = ("sex", "age", "stature_cm", "mass_kg")
ROW_KEYS = ("id", "source", "kind", "where", "read_off_plot", "mean", "sd", "sd_of", "unit", "quantity", "posture",
            "definition", "note", "garment", "probe")
GARMENT_KEYS = ("ease", "relaxed_cm", "fabric_modulus_N_per_m", "fabric")


@dataclass(frozen=True)
class Subjects:
    """Who a study measured: sex ('female', 'male', 'mixed') and the means it reports (SI; None if not)."""

    sex: str
    age: float | None = None
    stature: float | None = None  # m
    mass: float | None = None  # kg


@dataclass(frozen=True)
class Source:
    """One publication."""

    id: str
    authors: str
    year: int
    title: str
    journal: str
    method: str
    n: int
    subjects: Subjects
    url: str = ""
    doi: str = ""

    @property
    def citation(self) -> str:
        """'Authors (year), journal'."""
        return f"{self.authors} ({self.year}), {self.journal}"


@dataclass(frozen=True)
class GarmentSpec:
    """The garment of a pressure row: its size (ease against the body, or a relaxed circumference in m)
    and its fabric (a linear modulus in N/m, or tensile-curve points (strain, N/m)); None where not given."""

    ease: float | None = None
    relaxed: float | None = None
    modulus: float | None = None
    curve: tuple[tuple[float, float], ...] | None = None


@dataclass(frozen=True)
class Row:
    """One published figure: `mean` ± `sd` in `unit` of `quantity` (a `kind`), in `posture`."""

    id: str
    source: str
    kind: str
    where: str
    mean: float
    sd: float
    unit: str
    quantity: str
    definition: str
    posture: Mapping[str, float] = field(default_factory=dict)  # clinical angle name → degrees, as written
    sd_of: str = "change"
    read_off_plot: bool = False
    note: str = ""
    garment: GarmentSpec | None = None
    probe: str = ""  # a PROBES name: the oscillation is a local probe's tap, not the segment's resonance


@dataclass(frozen=True)
class Dataset:
    """A checked validation set: sources by id and rows in file order."""

    path: str
    sources: Mapping[str, Source]
    rows: tuple[Row, ...]

    def source_of(self, row: Row) -> Source:
        return self.sources[row.source]

    def supporting(self, kind: str, quantity: str) -> tuple[Row, ...]:
        """The rows of a kind whose quantity is `quantity` or, for skin strain, whose zone is its first word
        (a 'knee_right' zone's rows are the 'knee.*' ones)."""
        if kind == "skin_strain":
            zone = quantity.split("_")[0]
            return tuple(r for r in self.rows if r.kind == kind and r.quantity.split(".")[0] in (quantity, zone))
        return tuple(r for r in self.rows if r.kind == kind and r.quantity == quantity)

    def select(self, ids: tuple[str, ...] = (), kinds: tuple[str, ...] = ()) -> Dataset:
        """The rows with the given ids and/or kinds (all when none given); an unknown one is an error."""
        known_ids = {r.id for r in self.rows}
        for name in ids:
            if name not in known_ids:
                raise HitogataError(f"{self.path}: no row {name!r}; e.g. {', '.join(sorted(known_ids)[:3])}")
        for kind in kinds:
            if kind not in KINDS:
                raise HitogataError(f"row kind {kind!r}: allowed {', '.join(KINDS)}")
        rows = tuple(r for r in self.rows if (not ids or r.id in ids) and (not kinds or r.kind in kinds))
        if not rows:
            asked = " and ".join(x for x in (ids and f"ids {', '.join(ids)}", kinds and f"kinds {', '.join(kinds)}")
                                 if x)
            raise HitogataError(f"{self.path}: no row of {asked}")
        return Dataset(self.path, self.sources, rows)


def shipped_dataset_path() -> Path:
    """The validation set shipped with the package."""
    return Path(str(resources.files("hitogata").joinpath("data", "validation", SHIPPED_FILE)))


def load_dataset(path: str | Path | None = None) -> Dataset:
    """Read and check a validation file (the shipped set when `path` is None)."""
    source, doc = read_toml(shipped_dataset_path() if path is None else path)
    top = Entry(source, "file", doc, ("source", "row"))
    sources: dict[str, Source] = {}
    for k, table in enumerate(_tables(top, "source")):
        entry = Entry(source, f"[[source]] {k + 1}", table, SOURCE_KEYS)
        item = _source(entry)
        if item.id in sources:
            entry.fail(f"id {item.id!r} given twice; ids are unique")
        sources[item.id] = item
    rows: list[Row] = []
    seen: set[str] = set()
    for k, table in enumerate(_tables(top, "row")):
        name = table.get("id") if isinstance(table, dict) else None
        entry = Entry(source, f"row {name!r}" if isinstance(name, str) else f"[[row]] {k + 1}", table, ROW_KEYS)
        row = _row(entry, sources)
        if row.id in seen:
            entry.fail(f"id {row.id!r} given twice; ids are unique")
        seen.add(row.id)
        rows.append(row)
    if not rows:
        raise HitogataError(f"{source}: no [[row]]; a validation file holds at least one")
    return Dataset(source, MappingProxyType(sources), tuple(rows))


def _tables(top: Entry, key: str) -> list[Any]:
    tables = top.get(key, list, [])
    if not all(isinstance(t, dict) for t in tables):
        top.fail(f"{key} must be an array of tables ([[{key}]])")
    return tables


def _text(entry: Entry, key: str, default: Any = ...) -> str:
    value = entry.get(key, str, default)
    if default is ... and not value.strip():
        entry.fail("is empty; allowed a non-empty text", key)
    return value


def _source(entry: Entry) -> Source:
    year = entry.get("year", int)
    if not 1800 <= year <= 2100:
        entry.fail(f"{year!r}; allowed a year 1800..2100", "year")
    n = entry.get("n", int)
    if n < 1:
        entry.fail(f"{n!r}; allowed the number of subjects, a whole number >= 1", "n")
    sub = Entry(entry.source, f"{entry.where}.subjects", entry.get("subjects", dict), SUBJECT_KEYS)
    sex = sub.choice("sex", SEXES, "mixed") if sub.has("sex") else sub.fail("missing key 'sex'")
    age = _positive(sub, "age", 1.0, 90.0, "years 1..90")
    stature = _positive(sub, "stature_cm", 50.0, 230.0, "cm 50..230")
    mass = _positive(sub, "mass_kg", 8.0, 250.0, "kg 8..250")
    return Source(id=_text(entry, "id"), authors=_text(entry, "authors"), year=year, title=_text(entry, "title"),
                  journal=_text(entry, "journal"), method=_text(entry, "method"), n=n,
                  subjects=Subjects(sex, age, None if stature is None else stature / 100.0, mass),
                  url=_text(entry, "url", ""), doi=_text(entry, "doi", ""))


def _positive(entry: Entry, key: str, low: float, high: float, allowed: str) -> float | None:
    value = _optional(entry, key)
    if value is None:
        return None
    if not low <= value <= high:
        entry.fail(f"{value!r}; allowed {allowed}", key)
    return value


def _row(entry: Entry, sources: Mapping[str, Source]) -> Row:
    row_id = _text(entry, "id")
    source = _text(entry, "source")
    if source not in sources:
        known = ", ".join(sorted(sources)[:5]) or "none: add a [[source]] table"
        entry.fail(f"{source!r} is no [[source]] id; known: {known}", "source")
    kind = entry.choice("kind", KINDS, "") if entry.has("kind") else entry.fail("missing key 'kind'")
    unit = _text(entry, "unit")
    if unit not in UNITS[kind]:
        entry.fail(f"{unit!r} is not a unit of a {kind} row; allowed {', '.join(UNITS[kind])}", "unit")
    mean = entry.number("mean")
    sd = entry.number("sd")
    if sd < 0:
        entry.fail(f"{sd!r}; allowed a standard deviation >= 0", "sd")
    quantity = _text(entry, "quantity")
    _check_quantity(entry, kind, quantity)
    posture = _posture(entry) if kind in POSTURED else {}
    if entry.has("posture") and kind not in POSTURED:
        entry.fail(f"a {kind} row has no posture; allowed only in {', '.join(POSTURED)} rows", "posture")
    garment = _garment(entry) if kind == "pressure" and entry.get("garment", dict, {}) else None
    if entry.has("garment") and kind != "pressure":
        entry.fail(f"a {kind} row has no garment; allowed only in pressure rows", "garment")
    probe = _probe(entry, kind)
    return Row(id=row_id, source=source, kind=kind, where=_text(entry, "where"), mean=mean, sd=sd, unit=unit,
               quantity=quantity, definition=_text(entry, "definition"), posture=MappingProxyType(posture),
               sd_of=entry.choice("sd_of", SD_OF, "change"), read_off_plot=entry.get("read_off_plot", bool, False),
               note=_text(entry, "note", ""), garment=garment, probe=probe)


def _probe(entry: Entry, kind: str) -> str:
    """The row's local probe ('' where the oscillation is the segment's own, after an impact on its skeleton)."""
    if not entry.has("probe"):
        return ""
    if kind not in RESONANT:
        entry.fail(f"a {kind} row has no probe; allowed only in {', '.join(RESONANT)} rows", "probe")
    value = entry.get("probe", str)
    if value not in PROBES:
        entry.fail(f"{value!r}; allowed {', '.join(PROBES)} (a hand-held probe's tap on the tissue under it), or "
                   "no probe where an impact on the segment set its soft tissue ringing", "probe")
    return value


def _check_quantity(entry: Entry, kind: str, quantity: str) -> None:
    if kind == "posture_change":
        allowed: tuple[str, ...] = ("a measurement of hitogata measure, e.g. hip_girth", "waist_girth",
                                    "across_back_width")
        ok = quantity in MEASUREMENT_NAMES
    elif kind == "skin_strain":
        zone, _, direction = quantity.partition(".")
        allowed = tuple(f"{z}.{d}" for z in SKIN_ZONES for d in SKIN_DIRECTIONS)
        ok = zone in SKIN_ZONES and direction in SKIN_DIRECTIONS
    elif kind in ("frequency", "damping"):
        allowed = SOFT_TISSUE_REGIONS
        ok = quantity in allowed
    elif kind == "stiffness":
        parts = quantity.split(".")
        allowed = tuple(f"{t}.{m}.SITE" for t in TISSUES for m in MODULI)
        ok = len(parts) == 3 and parts[0] in TISSUES and parts[1] in MODULI and bool(parts[2])
    else:
        allowed = LEVELS
        ok = quantity in allowed
    if not ok:
        entry.fail(f"{quantity!r} is not a {kind} quantity; allowed {', '.join(allowed)}", "quantity")


def _posture(entry: Entry) -> dict[str, float]:
    table = entry.get("posture", dict, {})
    out = {}
    for name, value in table.items():
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            entry.fail(f"{name} = {value!r}; allowed an angle in degrees", "posture")
        out[str(name)] = float(value)
    return out


def _garment(entry: Entry) -> GarmentSpec:
    g = Entry(entry.source, f"{entry.where}.garment", entry.get("garment", dict), GARMENT_KEYS)
    ease = _optional(g, "ease")
    if ease is not None and not -0.9 <= ease <= 1.0:
        g.fail(f"{ease!r}; allowed -0.9..1 (relaxed circumference over the body's girth, - 1)", "ease")
    relaxed = _optional(g, "relaxed_cm")
    if relaxed is not None and not 5.0 <= relaxed <= 300.0:
        g.fail(f"{relaxed!r}; allowed a relaxed circumference of 5..300 cm", "relaxed_cm")
    if (ease is None) == (relaxed is None):
        g.fail("give the garment's size as one of ease or relaxed_cm")
    modulus = _optional(g, "fabric_modulus_N_per_m")
    if modulus is not None and not modulus > 0:
        g.fail(f"{modulus!r}; allowed a tension per unit strain > 0 N/m", "fabric_modulus_N_per_m")
    curve = _curve(g) if g.has("fabric") else None
    return GarmentSpec(ease=ease, relaxed=None if relaxed is None else relaxed / 100.0, modulus=modulus, curve=curve)


def _optional(entry: Entry, key: str) -> float | None:
    return entry.number(key) if entry.has(key) else None


def _curve(g: Entry) -> tuple[tuple[float, float], ...]:
    points = g.get("fabric", list)
    pairs = []
    for p in points:
        if (not isinstance(p, list) or len(p) != 2 or not all(isinstance(x, (int, float)) and not isinstance(x, bool)
                                                              and math.isfinite(x) and x >= 0 for x in p)):
            g.fail(f"point {p!r}; allowed [strain, tension_N_per_m] pairs of numbers >= 0", "fabric")
        pairs.append((float(p[0]), float(p[1])))
    if len(pairs) < 2 or any(b[0] <= a[0] for a, b in zip(pairs, pairs[1:])):
        g.fail(f"{points!r}; allowed two or more points with strains strictly increasing", "fabric")
    falls = next((b for a, b in zip(pairs, pairs[1:]) if b[1] <= a[1]), None)
    if falls is not None:  # a stretch fabric's tension rises with its strain: anything else is a typing slip
        g.fail(f"point {list(falls)!r}: the tension does not rise; allowed a tensile curve whose tension rises "
               "with the strain", "fabric")
    return tuple(pairs)
