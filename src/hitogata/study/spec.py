"""Study files (TOML): a population of bodies, the motions, the outputs, the model settings.

Read and checked before any work starts, with one-line errors naming the
file, the entry, the value and what is allowed (docs/study.md has the
format). The bodies come out as plain definitions (`BodyDef`) and the
motions as their scenario text (`MotionDef`), so a task can be sent to any
worker of a cluster without a shared file system.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

from hitogata import units
from hitogata.body import growth
from hitogata.body.model import STATURE_RANGE, WHOLE_BODY_DENSITY, check_density, sex_value
from hitogata.motion.scenario import load_scenario, shipped_scenarios
from hitogata.config import Entry, read_toml
from hitogata.errors import HitogataError
from hitogata.options import Skinning
from hitogata.body.shape import MIN_AGE_YEARS, OLD_YEARS
from hitogata.study.child_sampling import sample_children
from hitogata.study.sampling import SEXES, Joint, clusters, sample_stature_mass, sex_counts

OUTPUTS = ("measurements", "dynamic_ease", "zone_stretch")
Posing = Literal["skinning", "elastic"]
POSINGS: tuple[Posing, ...] = ("skinning", "elastic")
SKINNINGS: tuple[Skinning, ...] = ("dqs", "lbs")
MASS_RANGE = (30.0, 200.0)  # kg of an adult population's statistics; the shape solver says per body what it builds
AGE_RANGE = (MIN_AGE_YEARS, OLD_YEARS)  # below 18 years, stature and mass as the growth references allow
CHILD_SOURCE = ("stature from WHO height-for-age and BMI from WHO BMI-for-age (2006 to 5 years, 2007 after), "
                "independent, within their 0.1-99.9 percentiles, the mass within weight-for-age's and the shape's reach")
CHILD_STATURES = (0.5, STATURE_RANGE[1])  # m, a child's row; then checked against the growth references
CHILD_MASSES = (3.0, MASS_RANGE[1])  # kg, likewise
CHART_COLUMNS = {"stature": units.LENGTH_UNITS, "mass": units.MASS_UNITS, "age": {"years": 1.0}}


@dataclass(frozen=True)
class BodyDef:
    """One body of the population: by stature and mass, or by MakeHuman shape parameters (a file)."""

    id: str
    group: str  # the size, or the body cluster it belongs to
    sex: str
    age: float = 30.0
    stature: float | None = None  # m
    mass: float | None = None  # kg
    shape: tuple[tuple[str, Any], ...] | None = None  # ShapeParameters fields, for a body file
    density: float = WHOLE_BODY_DENSITY


@dataclass(frozen=True)
class MotionDef:
    """A motion by name, with its scenario file's text (parsed again where it runs)."""

    name: str
    text: str


@dataclass(frozen=True)
class ModelSettings:
    """How each body is moved: posing by skinning (cheap) or the elastic body; frames per motion."""

    posing: Posing = "skinning"
    skinning: Skinning = "dqs"
    frames: int = 9


@dataclass(frozen=True)
class StudySpec:
    """A checked study: bodies, motions, outputs and model settings, SI units."""

    source: str
    title: str
    seed: int
    bodies: tuple[BodyDef, ...]
    motions: tuple[MotionDef, ...]
    outputs: tuple[str, ...]
    model: ModelSettings
    population: str  # one line: where the bodies come from (source of the statistics, chart or folder)


def _need(entry: Entry, key: str, value: float | None) -> float:
    """A quantity the file must give: the value, or the missing key's one-line error."""
    if value is None:
        entry.fail(f"missing key {key!r}; it has no default")
    return value


def load_study(path: str | Path) -> StudySpec:
    """Read and check a study file; bodies, charts and motions named in it are read too."""
    path = Path(path)
    _, data = read_toml(path)
    return parse_study(data, path)


def parse_study(data: dict, path: Path) -> StudySpec:
    """Check a parsed study document; relative paths in it are relative to the file's folder."""
    source = str(path)
    top = Entry(source, "file", data, {"title", "seed", "motions", "outputs", "bodies", "model"})
    title = top.get("title", str, path.stem)
    seed = top.integer("seed", 0, 0, 2**63 - 1)
    motions = _motions(top, path.parent)
    outputs = data.get("outputs", list(OUTPUTS))
    if not (isinstance(outputs, list) and outputs and all(o in OUTPUTS for o in outputs)) or len(set(outputs)) < len(
        outputs
    ):
        top.fail(f"{outputs!r}; allowed a list of {', '.join(OUTPUTS)}, each once", "outputs")
    model = _model(Entry(source, "[model]", data.get("model", {}), {"posing", "skinning", "frames"}))
    bodies, population = _bodies(Entry(source, "[bodies]", top.get("bodies", dict), {
        "sampled", "female", "age", "clusters", "chart", "folder", "women", "men"}), path.parent, seed)
    return StudySpec(source, title, seed, bodies, motions, tuple(o for o in OUTPUTS if o in outputs), model,
                     population)


def _model(t: Entry) -> ModelSettings:
    return ModelSettings(t.choice("posing", POSINGS, "skinning"), t.choice("skinning", SKINNINGS, "dqs"),
                         t.integer("frames", 9, 2, 200))


def _motions(top: Entry, folder: Path) -> tuple[MotionDef, ...]:
    names = top.get("motions", list)
    if not (names and all(isinstance(n, str) and n for n in names)):
        top.fail(f"{names!r}; allowed a list of scenario names or files", "motions")
    shipped = shipped_scenarios()
    out: dict[str, MotionDef] = {}
    for name in names:
        file = shipped[name] if name in shipped else folder / name
        if not file.is_file():
            top.fail(f"{name!r}; allowed a scenario file or a shipped scenario: {', '.join(sorted(shipped))}",
                     "motions")
        load_scenario(file)  # checked here, once, with the scenario's own one-line errors
        stem = file.name.removesuffix(".toml")
        if stem in out:
            top.fail(f"{name!r}; allowed each motion once (two files with the same name)", "motions")
        out[stem] = MotionDef(stem, file.read_text(encoding="utf-8"))
    return tuple(out.values())


def _bodies(t: Entry, folder: Path, seed: int) -> tuple[tuple[BodyDef, ...], str]:
    kinds = [k for k in ("sampled", "chart", "folder") if k in t.table]
    if len(kinds) != 1:
        t.fail(f"{' and '.join(kinds) or 'none'} given; "
               "allowed exactly one of sampled (a count), chart (a CSV) or folder (body files)")
    if kinds[0] == "sampled":
        return _sampled(t, seed)
    if kinds[0] == "chart":
        return _chart(t, folder / str(t.table["chart"]))
    return _folder(t, folder / str(t.table["folder"]))


def _joint(t: Entry, sex: str) -> Joint:
    key = "women" if sex == "female" else "men"
    keys = {"stature_mean", "stature_sd", "mass_mean", "mass_sd", "correlation", "source"}
    if key not in t.table:
        t.fail(f"missing; allowed a table of {', '.join(sorted(keys))}", key)
    s = Entry(t.source, f"[bodies.{key}]", t.table[key], keys)
    lo, hi = STATURE_RANGE
    stature = "a length like 163cm"

    def need(name: str, table: dict[str, float], low: float, high: float, what: str) -> float:
        return _need(s, name, s.quantity(name, table, None, low, high, what))

    source = s.get("source", str)
    if not source.strip():
        s.fail(f"{source!r}; allowed the published survey the figures come from, as text", "source")
    return Joint(
        need("stature_mean", units.LENGTH_UNITS, lo, hi, f"{stature}, {lo * 100:.0f}..{hi * 100:.0f} cm"),
        need("stature_sd", units.LENGTH_UNITS, 1e-4, 0.3, f"{stature}, above 0 and up to 30 cm"),
        need("mass_mean", units.MASS_UNITS, *MASS_RANGE, f"a mass like 68kg, {MASS_RANGE[0]:g}..{MASS_RANGE[1]:g} kg"),
        need("mass_sd", units.MASS_UNITS, 1e-3, 60.0, "a mass like 11kg, above 0 and up to 60 kg"),
        need("correlation", {"": 1.0}, -0.99, 0.99, "a number -0.99..0.99"),
        source,
    )


def _sampled(t: Entry, seed: int) -> tuple[tuple[BodyDef, ...], str]:
    count = t.integer("sampled", 0, 1, 1_000_000)  # present: `_bodies` chose this kind by it
    share = t.quantity("female", units.FRACTION_UNITS, 0.5, 0.0, 1.0, "a share of women like 0.5 or 50%")
    age = t.quantity("age", {"": 1.0, "years": 1.0}, 30.0, *AGE_RANGE, f"years, {AGE_RANGE[0]:g}..{AGE_RANGE[1]:g}")
    k = t.integer("clusters", 3, 1, 50)
    child = growth.covers(age)
    if child and ("women" in t.table or "men" in t.table):
        t.fail(f"age {age:g} with {'women' if 'women' in t.table else 'men'} statistics; allowed for adults "
               "(18..90): children are drawn from the growth references", "women" if "women" in t.table else "men")
    bodies: list[BodyDef] = []
    sources = []
    for sex, n in sex_counts(count, share).items():
        if n == 0:
            continue
        if child:
            drawn = sample_children(sex, age, n, seed)
            values = drawn.values
            sources.append(f"{sex} {100 * (1 - drawn.kept_share):.1f} %")
        else:
            joint = _joint(t, sex)
            sources.append(f"{sex}: {joint.source}")
            values = sample_stature_mass(joint, n, seed, sex)
        labels = clusters(values, k, seed)
        names = {c: _cluster_name(sex, values[labels == c]) for c in set(labels.tolist())}
        bodies += [BodyDef(f"{sex}-{i:06d}", names[int(c)], sex, age, float(s), float(m))
                   for i, ((s, m), c) in enumerate(zip(values, labels))]
    if child:
        return tuple(bodies), (f"{count} sampled children aged {age:g} (seed {seed}): {CHILD_SOURCE}; "
                               f"draws drawn again: {', '.join(sources)}")
    return tuple(bodies), f"{count} sampled bodies (seed {seed}); " + "; ".join(sources)


def _cluster_name(sex: str, members: Any) -> str:
    stature, mass = members.mean(axis=0)
    return f"{sex} {stature * 100:.0f}cm {mass:.0f}kg"


def _chart(t: Entry, path: Path) -> tuple[tuple[BodyDef, ...], str]:
    """A size chart: a CSV with columns size, sex, stature_<unit>, mass_<unit> and optionally age_years."""
    try:
        rows = list(csv.reader(path.read_text(encoding="utf-8").splitlines()))
    except (FileNotFoundError, IsADirectoryError, UnicodeDecodeError):
        raise t.error(f"{str(path)!r}; allowed a size chart CSV (UTF-8) next to the study file", "chart") from None
    if not rows:
        raise HitogataError(f"{path}: empty; allowed a header size,sex,stature_cm,mass_kg[,age_years] and rows")
    header = [h.strip() for h in rows[0]]
    columns: dict[str, str | None] = {"size": None, "sex": None}
    for name, table in CHART_COLUMNS.items():
        found = [h for h in header if h.startswith(name + "_") and h.split("_", 1)[1] in table]
        columns[name] = found[0] if found else None
    missing = [n for n, c in columns.items() if c is None and n != "age" and n not in header]
    if missing:
        raise HitogataError(f"{path}: header {','.join(header)}: no {missing[0]!r} column; allowed "
                            "size,sex,stature_<cm|m|mm>,mass_<kg|g>[,age_years] (units in the header)")
    bodies = []
    for number, row in enumerate(rows[1:], start=2):
        if not any(cell.strip() for cell in row):
            continue
        if len(row) != len(header):
            raise HitogataError(f"{path}: row {number}: {len(row)} cells; allowed {len(header)} (the header's)")
        cells = dict(zip(header, (c.strip() for c in row)))
        size, sex = cells["size"], cells["sex"]
        where = f"{path}: row {number} (size {size!r})"
        if sex not in SEXES:
            raise HitogataError(f"{where}: sex {sex!r}; allowed {', '.join(SEXES)}")
        values: dict[str, float] = {}
        for name in ("age", "stature", "mass"):
            child = "age" in values and growth.covers(values["age"])
            low, high = {"age": AGE_RANGE, "stature": CHILD_STATURES if child else STATURE_RANGE,
                         "mass": CHILD_MASSES if child else MASS_RANGE}[name]
            column = columns.get(name)
            if column is None:
                values[name] = 30.0
                continue
            unit = column.split("_", 1)[1]
            try:
                value = float(cells[column]) * CHART_COLUMNS[name][unit]
            except ValueError:
                value = math.nan
            if not low <= value <= high:
                scale = {"stature": 100.0}.get(name, 1.0)
                raise HitogataError(f"{where}: {column} {cells[column]!r}; allowed a number "
                                    f"{low * scale:g}..{high * scale:g} {'cm' if name == 'stature' else unit}")
            values[name] = value
        if growth.covers(values["age"]):  # an adult's is refused where it is built, a row of the results
            try:
                growth.check_child(sex_value(sex), values["age"], values["stature"], values["mass"])
            except HitogataError as err:
                raise HitogataError(f"{where}: {err}") from None
        bodies.append(BodyDef(f"{size}-{number}", size, sex, values["age"], values["stature"], values["mass"]))
    if not bodies:
        raise HitogataError(f"{path}: no rows; allowed one row per size")
    return tuple(bodies), f"size chart {path.name}: {len(bodies)} rows"


def _folder(t: Entry, path: Path) -> tuple[tuple[BodyDef, ...], str]:
    """Body files (GLB written by `hitogata body`) in a folder: their shape parameters from the extras."""
    from hitogata.export.glb_read import read_glb_skin

    files = sorted(path.glob("*.glb")) if path.is_dir() else []
    if not files:
        t.fail(f"{str(path)!r}; allowed a folder holding .glb files written by `hitogata body`", "folder")
    bodies = []
    for file in files:
        extras = read_glb_skin(file).extras or {}
        shape = extras.get("shape")
        if not isinstance(shape, dict):
            raise HitogataError(f"{file}: no hitogata shape in the file's extras; allowed a .glb written by hitogata")
        shape = {**shape, "race": tuple(shape.get("race", (1 / 3,) * 3))}
        sex = "male" if float(shape.get("sex", 0.0)) >= 0.5 else "female"
        bodies.append(BodyDef(file.stem, sex, sex, float(shape.get("age", 30.0)), shape=tuple(sorted(shape.items())),
                              density=check_density(extras.get("density", WHOLE_BODY_DENSITY),
                                                            f"{file}: extras 'density'")))
    return tuple(bodies), f"{len(bodies)} body files in {path}"
