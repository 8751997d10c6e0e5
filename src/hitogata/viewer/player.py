"""The scenario player's data: a plain sequence of surfaces over time, its loaders and its clock.

The player shows a `Sequence` — times and a vertex array per frame, with
joint angles and rig joint centres when known — whatever produced it. Loaders
by kind of path (`load_sequence`):

- a `.npz` file with arrays `times` (T,) s, `vertices` (T, V, 3) m and
  optionally `angles` (T, D) rad (the 65-part skeleton, rest-relative) and
  `joints` (T, B, 3) m (the rig's joint centres, as `hitogata.measure` takes them);
- a results folder of `hitogata simulate`, holding such a file as
  `<scenario>_sequence.npz` (`export.motion_files.write_sequence`);
- a `.toml` file of pose keyframes (muscle contractions or clinical angles
  at times), posed kinematically by the body's Poser at `FRAME_RATE`;
- a dynamics scenario `.toml` (docs/scenarios.md), simulated on the viewer's
  body (elastic model and all: seconds, on a worker thread).

Every mistake is a one-line `HitogataError` naming the file.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hitogata.export.motion_files import find_sequence
from hitogata.dynamics.motion import simulate
from hitogata.simulation.run import build_dynamics
from hitogata.motion.scenario import load_scenario
from hitogata.errors import HitogataError
from hitogata.export.npz_read import read_npz
from hitogata.posing.pose import Poser
from hitogata.config import Entry, read_toml

RESULT_FILE = "sequence.npz"
SCENARIO_TABLES = {"body", "model", "time", "timeline", "output"}  # a dynamics scenario, not pose keyframes
FRAME_RATE = 30.0  # frames per second for keyframe files
MAX_FRAMES = 3000


@dataclass(frozen=True, eq=False)
class Sequence:
    """Surfaces of one body over time."""

    source: str
    times: np.ndarray  # (T,) s, increasing
    vertices: np.ndarray  # (T, V, 3) m
    angles: np.ndarray | None = None  # (T, D) rest-relative joint angles, rad
    joints: np.ndarray | None = None  # (T, B, 3) rig joint centres, m

    @property
    def start(self) -> float:
        return float(self.times[0])

    @property
    def end(self) -> float:
        return float(self.times[-1])

    def frame_at(self, time: float) -> int:
        """The frame shown at `time`: the last one that has begun (the first before the start)."""
        return int(np.clip(np.searchsorted(self.times, time, side="right") - 1, 0, len(self.times) - 1))


def check_sequence(seq: Sequence, n_vertices: int, n_dofs: int, n_bones: int) -> Sequence:
    """The sequence, if its arrays fit the body; else a one-line error naming the file."""
    times = seq.times
    if times.ndim != 1 or len(times) == 0 or not np.isfinite(times).all() or np.any(np.diff(times) <= 0):
        raise HitogataError(f"{seq.source}: times of shape {times.shape}: allowed a non-empty, finite, increasing 1-D array (s)")
    if len(times) > MAX_FRAMES:
        raise HitogataError(f"{seq.source}: {len(times)} frames: allowed at most {MAX_FRAMES}")
    shapes = {
        "vertices": (seq.vertices, (len(times), n_vertices, 3)),
        "angles": (seq.angles, (len(times), n_dofs)),
        "joints": (seq.joints, (len(times), n_bones, 3)),
    }
    for name, (array, shape) in shapes.items():
        if array is None:
            continue
        if array.shape != shape:
            raise HitogataError(f"{seq.source}: {name} of shape {array.shape}: allowed {shape} for this body")
        if not np.isfinite(array).all():
            raise HitogataError(f"{seq.source}: {name} has values that are not finite numbers")
    return seq


def load_npz(path: Path, poser: Poser) -> Sequence:
    """A sequence saved with numpy: `times`, `vertices`, optional `angles` and `joints`."""
    arrays = {k: np.asarray(v, dtype=np.float64) for k, v in read_npz(path).items() if v.dtype.kind in "biuf"}
    missing = [k for k in ("times", "vertices") if k not in arrays]
    if missing:
        raise HitogataError(f"{path}: no array {missing[0]!r}; a sequence has times, vertices (and angles, joints)")
    return Sequence(
        str(path), arrays["times"], arrays["vertices"].astype(np.float32), arrays.get("angles"), arrays.get("joints")
    )


def load_results_folder(path: Path, poser: Poser) -> Sequence:
    """The sequence a results folder of `hitogata simulate` holds."""
    return load_npz(find_sequence(path), poser)


def load_keyframes(path: Path, poser: Poser) -> Sequence:
    """Pose keyframes from TOML, joint angles interpolated linearly between them.

    ```toml
    [[keyframe]]
    time = 0.0                                  # s
    [[keyframe]]
    time = 1.0
    contractions = { biceps_brachii_r = 0.2 }   # fraction of rest length
    clinical = { "thigh_r.flexion" = 45.0 }     # degrees from the anatomical position
    ```
    """
    source, doc = read_toml(path)
    if SCENARIO_TABLES & doc.keys():
        return simulate_scenario(path, poser)
    if "keyframe" not in doc:
        raise HitogataError(f"{source}: no [[keyframe]] tables; allowed pose keyframes or a scenario (docs/scenarios.md)")
    Entry(source, "file", doc, ("keyframe",))
    tables = doc.get("keyframe")
    if not isinstance(tables, list) or len(tables) < 2:
        raise HitogataError(f"{source}: allowed two or more [[keyframe]] tables, each with a time")
    times, angles = [], []
    for k, table in enumerate(tables):
        entry = Entry(source, f"keyframe {k + 1}", table, ("time", "contractions", "clinical"))
        contractions = _numbers(entry, "contractions")
        clinical = {name: math.radians(value) for name, value in _numbers(entry, "clinical").items()}
        try:
            angles.append(poser.angles(contractions=contractions, clinical=clinical))
        except HitogataError as exc:
            entry.fail(str(exc))
        times.append(entry.number("time"))
    if np.any(np.diff(times) <= 0):
        raise HitogataError(f"{source}: keyframe times {times}: allowed increasing times")
    count = int(math.floor((times[-1] - times[0]) * FRAME_RATE)) + 1
    if count > MAX_FRAMES:
        raise HitogataError(f"{source}: {times[-1] - times[0]:g} s at {FRAME_RATE:g} fps: allowed at most {MAX_FRAMES} frames")
    frame_times = times[0] + np.arange(count) / FRAME_RATE
    q = np.stack([np.interp(frame_times, times, column) for column in np.array(angles).T], axis=1)
    return Sequence(source, frame_times, poser.pose_many(q).astype(np.float32), q, None)


def simulate_scenario(path: Path, poser: Poser) -> Sequence:
    """A dynamics scenario (docs/scenarios.md) simulated on the viewer's body, without writing files."""
    scenario = load_scenario(path)
    dynamics = build_dynamics(poser.body, scenario)
    motion = simulate(dynamics, scenario.timeline, scenario.duration, scenario.rate, scenario.substeps,
                      scenario.model.gravity, scenario.on_limit)
    joints = motion.rig_joints
    return Sequence(str(path), motion.times, motion.skin.astype(np.float32), motion.angles, joints)


def _numbers(entry: Entry, key: str) -> dict[str, float]:
    table = entry.get(key, dict, {})
    for name, value in table.items():
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            entry.fail(f"{key}.{name} = {value!r}: expected a finite number")
    return {name: float(value) for name, value in table.items()}


Loader = Callable[[Path, Poser], Sequence]
LOADERS: dict[str, Loader] = {".npz": load_npz, ".toml": load_keyframes}


def load_sequence(path: str | Path, poser: Poser) -> Sequence:
    """Load a sequence for the body of `poser` from a file or a results folder, checked against the body."""
    path = Path(str(path).strip()).expanduser()
    if path.is_dir():
        loader: Loader = load_results_folder
    elif not path.exists():
        raise HitogataError(f"{path}: no such file or folder")
    elif path.suffix.lower() in LOADERS:
        loader = LOADERS[path.suffix.lower()]
    else:
        raise HitogataError(f"{path}: unknown kind of file; allowed a results folder or {', '.join(LOADERS)}")
    seq = loader(path, poser)
    body = poser.body
    return check_sequence(seq, len(body.vertices), poser.skeleton.n_dofs, len(body.rig.names))


class Clock:
    """Playback time over [start, end]: play, pause, scrub; `advance` moves it while playing."""

    def __init__(self, start: float, end: float) -> None:
        self.start, self.end = start, end
        self.time, self.playing = start, False

    def play(self) -> None:
        """Play on; from the start again when at the end."""
        if self.time >= self.end:
            self.time = self.start
        self.playing = True

    def pause(self) -> None:
        self.playing = False

    def scrub(self, time: float) -> None:
        """Jump to a time (clipped to the sequence); playing goes on from there."""
        self.time = float(np.clip(time, self.start, self.end))

    def advance(self, seconds: float) -> float:
        """Move on by `seconds` while playing; stop at the end. Returns the time."""
        if self.playing:
            self.time = min(self.time + seconds, self.end)
            if self.time >= self.end:
                self.playing = False
        return self.time
