"""Scenario files (TOML): a body, its elastic model, a timeline of contractions and angles, outputs.

Read and checked in one place, with one-line errors naming the file and the
entry. The format is documented in docs/scenarios.md; the shipped examples
are in `hitogata/data/scenarios/`. Units as a person writes them
("165cm", "62kg", "40mm", "0.8s", "30deg", "2Hz", "10%") are turned into SI
here, once.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

from hitogata import units
from hitogata.body.model import Body, default_body
from hitogata.config import Entry, read_toml
from hitogata.dynamics.timeline import MAX_DURATION, MAX_RATE, MAX_SUBSTEPS, Keyframe, RootTrack, Timeline
from hitogata.errors import HitogataError
from hitogata.options import (
    ELEMENTS,
    EXTENTS,
    INTERPOLATIONS,
    MATERIALS_PRESETS,
    ON_LIMIT,
    OUTPUT_FILES as FILES,
    SEXES,
    SKINNING,
    VIEW_NAMES as VIEWS,
    Element,
    Extent,
    Interpolation,
    OnLimit,
    Skinning,
)
from hitogata.body.shape import MIN_AGE_YEARS, OLD_YEARS

TIME_UNITS = {"s": 1.0, "ms": 1e-3, "": 1.0}
FREQUENCY_UNITS = {"hz": 1.0}
LENGTH_MM = {"mm": 1.0, "cm": 10.0, "m": 1000.0, "": 1.0}
ANGLE_DEGREES = {**units.ANGLE_UNITS, "": math.pi / 180.0}
FRACTION = {"": 1.0, "%": 0.01}
SECTIONS = {"title", "body", "model", "time", "timeline", "keyframe", "output"}


@dataclass(frozen=True)
class BodySpec:
    """Who: sex, age (years), stature (m), mass (kg); or a shipped default body."""

    sex: str | float = "female"
    age: float = 30.0
    stature: float | None = None
    mass: float | None = None


@dataclass(frozen=True)
class ModelSpec:
    """The elastic model: extent, element size (mm or None), element, modes, damping, skinning, gravity."""

    extent: Extent = "body"
    element_size: float | None = None
    element: Element = "P2"
    modes: int = 40
    damping_ratios: tuple[tuple[float, float], tuple[float, float]] | None = None
    alpha_beta: tuple[float, float] | None = None
    skinning: Skinning = "dqs"
    gravity: bool = True
    materials: str | None = None  # a shipped preset's name or a materials file's path; None: the literature's


@dataclass(frozen=True)
class OutputSpec:
    """What to write: file kinds, views, picture size (pixels), snapshot times (s; None = automatic)."""

    files: tuple[str, ...] = FILES
    views: tuple[str, ...] = ("front", "side")
    size: tuple[int, int] = (360, 540)
    snapshots: tuple[float, ...] | None = None
    gif_rate: float = 15.0


@dataclass(frozen=True)
class Scenario:
    """One scenario file, checked and in SI units."""

    source: str
    title: str
    body: BodySpec
    model: ModelSpec
    duration: float
    rate: float
    substeps: int
    on_limit: OnLimit
    timeline: Timeline
    output: OutputSpec
    entries: tuple[KeyframeValue, ...] = ()  # every keyframe value as written, for checks that blame the user's line
    root: RootTrack | None = None  # the whole body's rigid motion (a BVH timeline's root); None: it stands


@dataclass(frozen=True)
class KeyframeValue:
    """One keyframe value: where it is in the file, as the user wrote it, and in SI."""

    keyframe: int  # 1-based, as `[[keyframe]] k` in messages
    table: str  # contractions, angles or clinical
    name: str
    written: Any
    value: float

    def where(self, source: str) -> str:
        return f"{source}: [[keyframe]] {self.keyframe}.{self.table}.{self.name} = {self.written!r}"


def load_scenario(path: str | Path) -> Scenario:
    """Read and check a scenario file."""
    source, data = read_toml(path)
    return parse_scenario(data, source)


def parse_scenario(data: dict, source: str) -> Scenario:
    """Check a parsed TOML document (see docs/scenarios.md)."""
    top = Entry(source, "file", data, SECTIONS)
    title = data.get("title", Path(source).stem)
    if not isinstance(title, str):
        raise top.error("expected a string", "title")
    body = _body(source, data.get("body", {}))
    model = _model(source, data.get("model", {}))
    time = Entry(source, "[time]", data.get("time", {}), {"duration", "rate", "substeps"})
    rate = time.quantity("rate", {"": 1.0, "/s": 1.0, "hz": 1.0}, 30.0, 1.0, MAX_RATE,
                         f"frames per second, 1..{MAX_RATE:g}")
    substeps = time.integer("substeps", 1, 1, MAX_SUBSTEPS)
    timeline_table = Entry(source, "[timeline]", data.get("timeline", {}),
                           {"interpolation", "on_limit", "bvh", "joint_map"})
    default_how = timeline_table.choice("interpolation", INTERPOLATIONS, "smoothstep")
    on_limit = timeline_table.choice("on_limit", ON_LIMIT, "raise")
    entries: list[KeyframeValue] = []
    root = None
    if "bvh" in timeline_table.table:  # the timeline read from a BVH file (docs/motion.md)
        from hitogata.motion.timeline import bvh_timeline
        keyframes, root = bvh_timeline(source, data, body)
    else:
        keyframes = _keyframes(source, data.get("keyframe", []), default_how, entries)
    timeline = Timeline.from_keyframes(keyframes)
    duration = time.quantity("duration", TIME_UNITS, None, 1e-3, MAX_DURATION,
                             f"a time in s, up to {MAX_DURATION:g} s")
    duration = duration if duration is not None else min(max(timeline.end + 1.0, 1.0), MAX_DURATION)
    output = _output(source, data.get("output", {}), duration)
    return Scenario(source, title, body, model, duration, rate, substeps, on_limit, timeline, output, tuple(entries),
                    root)


def _body(source: str, table: Any) -> BodySpec:
    r = Entry(source, "[body]", table, {"sex", "age", "stature", "mass"})
    sex = table.get("sex", "female")
    number = isinstance(sex, (int, float)) and not isinstance(sex, bool)
    if not (sex in SEXES or (number and 0 <= sex <= 1)):
        raise r.error(f"{sex!r}; allowed female, male or a number 0 (female) … 1 (male)", "sex")
    age = r.quantity("age", {"": 1.0, "years": 1.0, "y": 1.0}, 30.0, MIN_AGE_YEARS, OLD_YEARS,
                     f"years, {MIN_AGE_YEARS:g}..{OLD_YEARS:g}")
    stature = r.quantity("stature", units.LENGTH_UNITS, None, 0.5, 2.5, "a length like 165cm")
    mass = r.quantity("mass", units.MASS_UNITS, None, 3.0, 250.0, "a mass like 62kg")
    if (stature is None) != (mass is None):
        raise r.error("give stature and mass together (or neither: the default body)",
                      "stature" if stature is None else "mass")
    if stature is not None and mass is not None:
        from hitogata.body.model import check_stature_mass  # here: the body module loads the shape data

        try:
            check_stature_mass(sex, age, stature, mass)
        except HitogataError as err:
            raise r.error(str(err)) from None
    return BodySpec(sex, age, stature, mass)


def _model(source: str, table: Any) -> ModelSpec:
    r = Entry(source, "[model]", table, {"extent", "element_size", "element", "modes", "damping", "rayleigh",
                                           "skinning", "gravity", "materials"})
    size = r.quantity("element_size", LENGTH_MM, None, 4.0, 100.0, "a length like 40mm (4..100 mm)")
    ratios = alpha_beta = None
    if "damping" in table and "rayleigh" in table:
        raise r.error("give damping or rayleigh, not both", "damping")
    if "damping" in table:
        pairs = table["damping"]
        if not (isinstance(pairs, list) and len(pairs) == 2):
            raise r.error("expected two entries like { frequency = \"2Hz\", ratio = 0.2 }", "damping")
        parsed = []
        for k, pair in enumerate(pairs):
            p = Entry(source, f"[model].damping[{k}]", pair, {"frequency", "ratio"})
            f = p.quantity("frequency", FREQUENCY_UNITS, None, 1e-3, 1e4, "a frequency like 2Hz")
            z = p.quantity("ratio", FRACTION, None, 0.0, 10.0, "a damping ratio like 0.2 or 20%")
            if f is None or z is None:
                raise p.error("missing", "frequency" if f is None else "ratio")
            parsed.append((f, z))
        if parsed[0][0] == parsed[1][0]:
            raise r.error("the two frequencies must differ", "damping")
        ratios = (parsed[0], parsed[1])
    if "rayleigh" in table:
        p = Entry(source, "[model].rayleigh", table["rayleigh"], {"alpha", "beta"})
        alpha_beta = (p.quantity("alpha", {"": 1.0, "/s": 1.0}, 0.0, 0.0, 1e4, "alpha in 1/s, >= 0"),
                      p.quantity("beta", TIME_UNITS, 0.0, 0.0, 10.0, "beta in s, >= 0"))
    gravity = table.get("gravity", True)
    if not isinstance(gravity, bool):
        raise r.error(f"{gravity!r}; allowed true or false", "gravity")
    return ModelSpec(r.choice("extent", EXTENTS, ModelSpec.extent), size, r.choice("element", ELEMENTS, "P2"),
                     r.integer("modes", 40, 1, 400), ratios, alpha_beta, r.choice("skinning", SKINNING, "dqs"),
                     gravity, _materials(source, table.get("materials")))


def _materials(source: str, name: Any) -> str | None:
    """[model].materials: a shipped preset (`options.MATERIALS_PRESETS`) or a materials file beside the scenario,
    read and checked here (a mistake is said before any long work)."""
    if name is None:
        return None
    from hitogata.elastic.materials import load_materials
    from hitogata.motion.timeline import beside

    path = name if name in MATERIALS_PRESETS else str(beside(source, "[model].materials", name))
    load_materials(path)
    return path


CHANNELS = {"contractions": ("contraction", FRACTION, "a contraction like 0.1 or -10%"),
            "angles": ("angle", ANGLE_DEGREES, "an angle like 30deg (a bare number is degrees)"),
            "clinical": ("clinical", ANGLE_DEGREES, "an angle like 30deg (a bare number is degrees)")}


def _keyframes(source: str, entries: Any, default_how: Interpolation, written: list[KeyframeValue]) -> list[Keyframe]:
    if not isinstance(entries, list) or not entries:
        raise HitogataError(f"{source}: [[keyframe]]: at least one keyframe is needed")
    out, last = [], -math.inf
    for k, entry in enumerate(entries, start=1):
        entry_name = f"[[keyframe]] {k}"
        r = Entry(source, entry_name, entry, {"time", "interpolation", *CHANNELS})
        t = r.quantity("time", TIME_UNITS, None, 0.0, MAX_DURATION, f"a time like 0.8s, up to {MAX_DURATION:g} s")
        if t is None:
            raise r.error("missing", "time")
        if t <= last:
            raise r.error(f"{entry['time']!r} is not after the previous keyframe's {last:g} s", "time")
        last = t
        values: dict[tuple[str, str], float] = {}
        for key, (kind, unit_table, what) in CHANNELS.items():
            given = _dotted(entry.get(key, {}))
            channel = Entry(source, f"{entry_name}.{key}", given, set(given) if isinstance(given, dict) else set())
            for name, value in channel.table.items():
                number = channel.quantity(name, unit_table, None, -math.inf, math.inf, what)
                if number is None:  # not reached: the name comes from the table
                    raise channel.error("missing", name)
                if kind == "contraction" and not str(value).strip().endswith("%") and abs(number) >= 1.0:
                    raise channel.error(f"{value!r}: a contraction is a fraction of the rest length, "
                                             f"allowed between -1 and 1; did you mean {value}%?", name)
                values[(kind, name)] = number
                written.append(KeyframeValue(k, key, name, value, number))
        out.append(Keyframe(t, values, r.choice("interpolation", INTERPOLATIONS, default_how)))
    return out


def _dotted(table: Any) -> Any:
    """{knee_r = {flexion = 30}} (TOML's reading of the unquoted `knee_r.flexion = 30`) → {"knee_r.flexion": 30}."""
    if not isinstance(table, dict):
        return table
    flat: dict[str, Any] = {}
    for name, value in table.items():
        if isinstance(value, dict):
            flat.update({f"{name}.{dof}": v for dof, v in value.items()})
        else:
            flat[name] = value
    return flat


def _output(source: str, table: Any, duration: float) -> OutputSpec:
    r = Entry(source, "[output]", table, {"files", "views", "size", "snapshots", "gif_rate"})
    files = table.get("files", list(FILES))
    if not isinstance(files, list) or any(f not in FILES for f in files):
        raise r.error(f"{files!r}; allowed a list of {', '.join(FILES)}", "files")
    views = table.get("views", ["front", "side"])
    if not isinstance(views, list) or not views or any(v not in VIEWS for v in views):
        raise r.error(f"{views!r}; allowed a list of {', '.join(VIEWS)}", "views")
    size = table.get("size", [360, 540])
    if not (isinstance(size, list) and len(size) == 2 and all(isinstance(s, int) and 64 <= s <= 4096 for s in size)):
        raise r.error(f"{size!r}; allowed [width, height] in pixels, 64..4096", "size")
    snapshots = None
    if "snapshots" in table:
        raw = table["snapshots"]
        if not isinstance(raw, list):
            raise r.error("expected a list of times like [\"0.8s\", \"2s\"]", "snapshots")
        listed = {str(i): v for i, v in enumerate(raw)}
        shot = Entry(source, "[output].snapshots", listed, set(listed))
        times = []
        for i in range(len(raw)):
            t = shot.quantity(str(i), TIME_UNITS, None, 0.0, duration, f"a time within 0..{duration:g} s")
            if t is None:  # not reached: every index is in the table
                raise shot.error("missing", str(i))
            times.append(t)
        snapshots = tuple(times)
    gif_rate = r.quantity("gif_rate", {"": 1.0, "/s": 1.0, "hz": 1.0}, 15.0, 1.0, 60.0, "frames per second, 1..60")
    return OutputSpec(tuple(files), tuple(views), (size[0], size[1]), snapshots, gif_rate)


def shipped_scenarios() -> dict[str, Path]:
    """The example scenarios shipped with the package, by name."""
    folder = resources.files("hitogata") / "data" / "scenarios"
    return {p.name.removesuffix(".toml"): Path(str(p)) for p in folder.iterdir() if p.name.endswith(".toml")}


def make_body(spec: BodySpec) -> Body:
    """The scenario's body: from stature and mass, or the shipped default of that sex."""
    if spec.stature is None:
        if spec.sex not in ("female", "male"):
            raise HitogataError(f"body sex {spec.sex!r} without stature and mass: the default bodies are female, male")
        return default_body(spec.sex)
    return Body.from_measurements(sex=spec.sex, age=spec.age, stature=spec.stature, mass=spec.mass)
