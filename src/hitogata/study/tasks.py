"""One task of a study: one body through one motion → its rows of figures.

A task is plain data (`Task`), named by a hash of its definition so a
rerun can tell it is done. `execute` runs it anywhere — in a plain loop or
on a Dask worker — and never raises for a bad body or motion: the error
comes back as one line. What does not depend on the body (the skeleton and
muscle lists, the MakeHuman assets, the mesh topology, the reference
landmarks) is loaded once per process (`warm`, which the runner's worker
plugin calls when a worker starts); the last few bodies prepared are kept,
since a body's motions often run on the same worker.

Per measurement: its standing value, its least and largest value through
the motion, and the dynamic ease — the largest increase over standing (the
least ease a woven garment needs there) and the largest decrease. Per
zone: the largest 95th-percentile skin stretch over the motion (the stretch
a close-fitting fabric must allow there), the largest mean stretch, the
most compression and the largest area change.
"""

from __future__ import annotations

import hashlib
import json
import time
import tomllib
from dataclasses import asdict, dataclass
from functools import cache, lru_cache
from typing import TYPE_CHECKING

import numpy as np
from threadpoolctl import threadpool_limits

from hitogata.study.spec import BodyDef, ModelSettings, MotionDef

if TYPE_CHECKING:  # for the annotations only: the functions below import what they run where they run it
    from hitogata.body.model import Body
    from hitogata.posing.pose import Poser

ROWS_VERSION = 5  # part of every task's hash: bump when a row's meaning changes, so old rows are not reused
# (3: waist_girth is ISO 8559-1's waist, the navel's is omphalion_waist_girth; the neck girth at its
# narrowest; seven measurements added; 4: the iliac crest's waist girth and height added; 5: the
# crotch carried by the pelvis, the front and back rise added)
# Figures are stored rounded to this many decimals (nanometres, 1e-9 %): the last bit of a sum in
# numpy depends on the memory alignment of its array (SIMD blocks), so the same task gave a thigh
# girth of 0.5735926758767658 m in one process and ...657 in another; rounded, the bits agree.
DECIMALS = 9

# Row columns and their kinds: "str", "float". Lengths in m, strains in %, times in s.
COLUMNS: dict[str, str] = {
    "task": "str", "body": "str", "group": "str", "sex": "str", "age": "float", "stature_m": "float",
    "mass_kg": "float", "motion": "str", "kind": "str", "name": "str",
    "standing_m": "float", "low_m": "float", "high_m": "float",
    "ease_increase_m": "float", "ease_decrease_m": "float",
    "stretch_p95_pct": "float", "stretch_mean_pct": "float", "compression_pct": "float",
    "area_change_pct": "float", "peak_time_s": "float",
}


@dataclass(frozen=True)
class Task:
    """One body through one motion, with the model settings and the outputs wanted."""

    body: BodyDef
    motion: MotionDef
    model: ModelSettings
    outputs: tuple[str, ...]

    @property
    def key(self) -> str:
        """16 hex digits of a hash of everything the rows depend on."""
        definition = {"version": ROWS_VERSION, **asdict(self)}
        text = json.dumps(definition, sort_keys=True, default=list)
        return hashlib.sha256(text.encode()).hexdigest()[:16]


@dataclass(frozen=True)
class Outcome:
    """What a task gives back: its rows (column → values) or its one-line error; its wall and CPU time (s)."""

    key: str
    rows: dict[str, list] | None
    error: str | None
    seconds: float
    cpu_seconds: float = 0.0


def execute(task: Task) -> Outcome:
    """Run a task; a failure of any kind comes back as its one-line error, never raised.

    BLAS runs on one thread, as on a Dask worker (its nanny sets OMP_NUM_THREADS=1): the
    same task then gives the same bits in a plain loop and on a cluster.
    """
    start, cpu = time.perf_counter(), time.process_time()
    rows: dict[str, list] | None
    error: str | None
    try:
        with threadpool_limits(1):
            rows = task_rows(task)
    except Exception as err:  # recorded for the user; the study goes on with the other tasks
        message = " ".join(str(err).split()) or "no message"
        rows, error = None, f"{type(err).__name__}: {message}"
    else:
        error = None
    return Outcome(task.key, rows, error, time.perf_counter() - start, time.process_time() - cpu)


@cache
def shared_lists():
    """The shipped skeleton and muscle lists, read once per process."""
    from hitogata.muscles.spec import load_muscle_spec
    from hitogata.skeleton.spec import load_skeleton_spec

    skeleton = load_skeleton_spec()
    return skeleton, load_muscle_spec(skeleton)


def warm() -> None:
    """Load everything that does not depend on the body, once per process (a worker's start-up)."""
    from hitogata.body.assets import load_assets
    from hitogata.measure.landmarks import reference_vertices
    from hitogata.geometry.topology import topology

    assets = load_assets()
    shared_lists()
    topology(assets.triangles)
    reference_vertices()


@dataclass(frozen=True, eq=False)
class Prepared:
    """A built body, its poser and its standing measurements."""

    body: Body
    poser: Poser
    standing: dict[str, float]


@lru_cache(maxsize=4)
def prepared(definition: BodyDef) -> Prepared:
    """Build a body (stature and mass solved, or from shape parameters) and place its skeleton."""
    from hitogata.body.model import Body
    from hitogata.measure import measure
    from hitogata.muscles.geometry import place_muscles
    from hitogata.posing.pose import Poser
    from hitogata.body.shape import ShapeParameters
    from hitogata.skeleton.kinematics import Kinematics
    from hitogata.skeleton.child_ranges import with_age_ranges
    from hitogata.skeleton.placement import place_skeleton
    from hitogata.skeleton.weights import part_weights
    from hitogata.posing.skinning import prepare_skin

    if definition.shape is not None:
        body = Body.from_parameters(ShapeParameters(**dict(definition.shape)), definition.density)
    else:
        body = Body.from_measurements(definition.sex, definition.age, definition.stature, definition.mass,
                                      density=definition.density)
    # Poser.from_body with the lists read once per process instead of once per body.
    spec, muscle_spec = shared_lists()
    skeleton = with_age_ranges(place_skeleton(spec, body.rig), body.params.sex, body.params.age)
    weights = part_weights(skeleton, body.rig, body.skin_weights, body.vertices)
    poser = Poser(body, skeleton, place_muscles(muscle_spec, skeleton), Kinematics(skeleton),
                  prepare_skin(body.vertices, weights, skeleton.parents))
    return Prepared(body, poser, measure(body).as_dict())


@lru_cache(maxsize=16)
def scenario_of(motion: MotionDef):
    """The motion's scenario, parsed from its text (already checked where the study was read)."""
    from hitogata.motion.scenario import parse_scenario

    return parse_scenario(tomllib.loads(motion.text), motion.name)


def frame_times(scenario, frames: int) -> np.ndarray:
    """`frames` times evenly over the scenario, plus its keyframes' times (where motions peak)."""
    keys = [t for c in scenario.timeline.channels for t in c.times if t <= scenario.duration]
    return np.unique(np.concatenate([np.linspace(0.0, scenario.duration, frames), keys]))


def postures(prep: Prepared, scenario, times: np.ndarray, model: ModelSettings) -> tuple[np.ndarray, np.ndarray]:
    """Skin vertices (T, V, 3) and rig joint centres (T, B, 3) of the body at `times`."""
    from hitogata.dynamics.motion import _angles as timeline_angles
    from hitogata.body.rig import posed_rig_heads
    from hitogata.posing.skinning import skin_vertices

    poser, body = prep.poser, prep.body
    if model.posing == "elastic":
        return _elastic_postures(prep, scenario, times)
    sk = poser.skeleton
    rest = {("clinical", c.name): float(sk.rest[sk.dof_names.index(c.name)]) for c in scenario.timeline.channels
            if c.kind == "clinical" and c.name in sk.dof_names}
    angles = timeline_angles(poser, scenario.timeline.sample(times, rest), len(times), scenario.on_limit)
    pose = poser.kinematics.pose(angles)
    vertices = skin_vertices(poser.skin, pose.rotations, pose.translations, model.skinning)
    joints = np.stack([posed_rig_heads(body.rig.heads, sk.joints, r, t)
                       for r, t in zip(pose.rotations, pose.translations)])
    return vertices, joints


def _elastic_postures(prep: Prepared, scenario, times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The elastic body simulated at the scenario's rate (its own [model]), taken at the nearest frames."""
    from hitogata.dynamics.motion import simulate
    from hitogata.simulation.run import build_dynamics
    from hitogata.body.rig import posed_rig_heads

    dynamics = build_dynamics(prep.body, scenario)
    motion = simulate(dynamics, scenario.timeline, scenario.duration, scenario.rate, scenario.substeps,
                      scenario.model.gravity, scenario.on_limit)
    pick = np.clip(np.round(times * scenario.rate).astype(int), 0, len(motion.times) - 1)
    sk = prep.poser.skeleton
    joints = np.stack([posed_rig_heads(prep.body.rig.heads, sk.joints, motion.rotations[k], motion.translations[k])
                       for k in pick])
    return motion.skin[pick].astype(np.float64), joints


def dynamic_ease(standing: float, values: np.ndarray) -> tuple[float, float]:
    """The largest increase (≥ 0) and the largest decrease (≤ 0) of a measurement over standing (m).

    The same definition as the garment package's dynamic ease (`garment.ease`); this is where
    a study can call it.
    """
    if not np.isfinite(values).any():
        return float("nan"), float("nan")
    change = values - standing
    return max(float(np.nanmax(change)), 0.0), min(float(np.nanmin(change)), 0.0)


def task_rows(task: Task) -> dict[str, list]:
    """The rows of one task: one per measurement and one per zone, as wanted by `task.outputs`."""
    from hitogata.garment.ease import HEIGHTS, STANDING_ONLY
    from hitogata.measure.axes import JointSet
    from hitogata.measure.landmarks import body_landmarks
    from hitogata.measure.measurements import GIRTHS, MEASUREMENT_NAMES, measure_surface, tape_skin
    from hitogata.measure.strain import skin_strain
    from hitogata.measure.zones import ZONE_NAMES, zone_strains

    prep = prepared(task.body)
    scenario = scenario_of(task.motion)
    times = frame_times(scenario, task.model.frames)
    vertices, joints = postures(prep, scenario, times, task.model)
    body = prep.body
    want_measures = "measurements" in task.outputs or "dynamic_ease" in task.outputs
    want_zones = "zone_stretch" in task.outputs
    marks, rest, skin = body_landmarks(body), JointSet(body.rig.names, body.rig.heads), tape_skin(body)
    values = np.full((len(times), len(MEASUREMENT_NAMES)), np.nan)
    zones = np.full((len(times), len(ZONE_NAMES), 4), np.nan)  # p95, mean, compression, area change
    for k, (v, j) in enumerate(zip(vertices, joints)):
        if want_measures:
            m = measure_surface(v, body.faces, marks, rest, JointSet(body.rig.names, j), skin)
            values[k] = [m.get(name) for name in MEASUREMENT_NAMES]
        if want_zones:
            strains = zone_strains(body, skin_strain(body.vertices, v, body.faces))
            zones[k] = [[s.stretch_p95, s.stretch_mean, s.compression_mean, s.area_change]
                        for s in (strains[z] for z in ZONE_NAMES)]

    rows: dict[str, list] = {name: [] for name in COLUMNS}
    common = {"task": task.key, "body": task.body.id, "group": task.body.group, "sex": task.body.sex,
              "age": float(task.body.age), "stature_m": float(body.stature), "mass_kg": float(body.mass),
              "motion": task.motion.name}
    nan = float("nan")

    def add(**fields) -> None:
        for column in COLUMNS:
            rows[column].append(fields.get(column, common.get(column, nan)))

    if want_measures:
        ease = "dynamic_ease" in task.outputs
        for i, name in enumerate(MEASUREMENT_NAMES):
            series, standing = values[:, i], prep.standing[name]
            kind = "girth" if name in GIRTHS else "height" if name in HEIGHTS else "length"
            undefined = name in STANDING_ONLY or name in HEIGHTS  # no meaning in a motion: nan, never a number
            increase, decrease = dynamic_ease(standing, series) if ease and not undefined else (nan, nan)
            finite = np.isfinite(series).any()
            add(kind=kind, name=name, standing_m=standing,
                low_m=float(np.nanmin(series)) if finite else nan, high_m=float(np.nanmax(series)) if finite else nan,
                ease_increase_m=increase, ease_decrease_m=decrease,
                peak_time_s=peak_time(times, series) if finite else nan)
    if want_zones:
        for i, name in enumerate(ZONE_NAMES):
            p95, mean, compression, area = zones[:, i].T
            add(kind="zone", name=name, stretch_p95_pct=float(np.nanmax(p95)), stretch_mean_pct=float(np.nanmax(mean)),
                compression_pct=float(np.nanmin(compression)), area_change_pct=float(np.nanmax(area)),
                peak_time_s=peak_time(times, p95))
    for column, kind in COLUMNS.items():
        if kind == "float":
            rows[column] = [round(value, DECIMALS) for value in rows[column]]
    return rows


def peak_time(times: np.ndarray, series: np.ndarray) -> float:
    """The first time the series comes within round-off (10^-DECIMALS) of its largest value: a
    measurement the motion leaves unchanged peaks at the start, whatever its last bits do."""
    return float(times[np.flatnonzero(series >= np.nanmax(series) - 10.0 ** -DECIMALS)[0]])
