"""Dynamic ease: how much each girth and length grows and shrinks through a set of motions.

For a body and motions (skeleton clips), every sampled frame's surface (a
parameter, any function of the joint angles and root motion: the skinned
surface by default, or the elastic whole body's, each frame held with its
skin's self-contact resolved, `elastic_surface`) is measured
with `hitogata.measure` (the ISO 8559-1 measurements, the across-back and
across-front widths among them). Against the standing body:
the largest increase (the least ease a woven garment needs there) and the
largest decrease, with when they happen, per motion and over all motions.
Tables here; the plot is in `garment.ease_plot` (computation never imports it).
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from hitogata.body.model import Body
from hitogata.errors import HitogataError
from hitogata.measure.axes import JointSet
from hitogata.measure.landmarks import body_landmarks
from hitogata.measure.measurements import MEASUREMENT_NAMES, measure_surface, posture_arrays, tape_skin
from hitogata.measure.values import HEIGHTS, undefined_because
from hitogata.options import Skinning
from hitogata.body.rig import posed_rig_heads
from hitogata.motion.clip import MotionClip
from hitogata.posing.pose import poser_for

if TYPE_CHECKING:
    from hitogata.elastic.materials import Materials

# The armscye is a standing measurement: its plane is set by the arm's own armpit folds, so with the arm
# raised the tape loops round the shoulder (+33 cm reaching forward), which is no armhole's need.
STANDING_ONLY = ("armscye_girth",)
NAMES = tuple(n for n in MEASUREMENT_NAMES if n not in STANDING_ONLY)
# Heights above the floor (`HEIGHTS`; ISO 8559-1 takes them standing upright) have no meaning once the body
# bends, sits or strides (an inside leg while touching the toes), so dynamic ease reports them as undefined.
UNDEFINED = "a height above the floor: ISO 8559-1 takes it standing upright, it has no meaning in a motion"
Surface = Callable[[np.ndarray, np.ndarray], np.ndarray]  # (F, D) angles, (F, 4, 4) root → (F, V, 3) vertices


@dataclass(frozen=True)
class MotionEase:
    """One motion: sampled times (T,), values (T, M) in metres, the standing values (M,)."""

    motion: str
    times: np.ndarray
    values: np.ndarray
    standing: np.ndarray

    @property
    def change(self) -> np.ndarray:
        """(T, M) change from standing, metres."""
        return self.values - self.standing

    def largest(self) -> list[dict]:
        """Per measurement: standing, largest increase and decrease (cm, %) and when (s), over the frames where
        it is defined; None where it has no meaning in a motion (`HEIGHTS`) or in none of its frames (the knee
        girth in a deep squat), with the reason in 'undefined' (which also says so where some frames lacked it)."""
        rows = []
        for m, name in enumerate(NAMES):
            standing = self.standing[m]
            change = self.change[:, m]
            defined = np.isfinite(change)
            if name in HEIGHTS or not defined.any():
                rows.append({"motion": self.motion, "measurement": name, "standing_cm": 100 * standing,
                             **{k: None for k in ("increase_cm", "increase_pct", "increase_at_s", "decrease_cm",
                                                  "decrease_pct", "decrease_at_s")},
                             "undefined": UNDEFINED if name in HEIGHTS else f"in every frame: {undefined_because(name)}"})
                continue
            up, down = int(np.nanargmax(change)), int(np.nanargmin(change))
            row = {"motion": self.motion, "measurement": name, "standing_cm": 100 * standing,
                   "increase_cm": max(100 * change[up], 0.0),
                   "increase_pct": max(100 * change[up] / standing, 0.0),
                   "increase_at_s": float(self.times[up]),
                   "decrease_cm": min(100 * change[down], 0.0),
                   "decrease_pct": min(100 * change[down] / standing, 0.0),
                   "decrease_at_s": float(self.times[down])}
            if not defined.all():
                missing = self.times[~defined]
                when = f"{missing.min():g}" + (f"-{missing.max():g}" if len(missing) > 1 else "")
                row["undefined"] = (f"in {len(missing)} of {len(change)} frames ({when} s; the figures are of the "
                                    f"others): {undefined_because(name)}")
            rows.append(row)
        return rows


def skinned_surface(body: Body, skinning: Skinning = "dqs") -> Surface:
    """The surface source: the body skinned onto the posed skeleton ('dqs' or 'lbs')."""
    poser = poser_for(body)
    return lambda angles, root: poser.pose_many(angles, skinning, root)


def elastic_surface(body: Body, contact: bool = True, workers: int | None = 1,
                    materials: Materials | None = None) -> Surface:
    """The surface source of the elastic whole body (on DQS): each frame's posture held (quasi-statics from
    rest, no loads), its skin's self-contact resolved and its creases folded with `contact`
    (`skin.single_pose.elastic_pose`), then moved by the frame's root. The frames are held on `workers`
    processes (`skin.held_frames`, the same answers; None: the cores free of other work, as `hitogata ease`
    does: a script
    doing so needs the `if __name__ == "__main__":` guard of any spawned process pool); `materials`: the
    tissue's (None: the literature's). A frame asked for again (ease, stretch and pressure each ask for the
    same frames) is not solved again."""
    from hitogata.skin.held_frames import HeldFrames

    hold = HeldFrames(body, contact, workers, materials)
    held: dict[bytes, np.ndarray] = {}

    def surface(angles: np.ndarray, root: np.ndarray) -> np.ndarray:
        angles = np.atleast_2d(np.asarray(angles, dtype=float))
        # a clip's angles were checked with its scenario: a clamp only rounds off a hair
        new = {q.tobytes(): q for q in angles if q.tobytes() not in held}
        held.update(zip(new, hold(np.array(list(new.values())).reshape(-1, angles.shape[1]))))
        out = np.empty((len(angles), len(body.vertices), 3))
        for k, (q, r) in enumerate(zip(angles, root)):
            out[k] = held[q.tobytes()] @ r[:3, :3].T + r[:3, 3]
        return out

    return surface


def motion_ease(body: Body, name: str, clip: MotionClip, surface: Surface | None = None,
                rate: float = 5.0) -> MotionEase:
    """Every measurement of one motion, sampled at `rate` frames per second (its first and last frames kept)."""
    surface = surface or skinned_surface(body)
    frames = sampled_frames(clip, rate)
    poser = poser_for(body)
    pose = poser.kinematics.pose(clip.angles[frames], root=clip.root[frames])
    vertices = surface(clip.angles[frames], clip.root[frames])
    values = np.array([_measure(body, vertices[k], posed_rig_heads(body.rig.heads, poser.skeleton.joints,
                                                                    pose.rotations[k], pose.translations[k]))
                       for k in range(len(frames))])
    standing = _measure(body, body.vertices, body.rig.heads)
    return MotionEase(name, clip.times[frames], values, standing)


def sampled_frames(clip: MotionClip, rate: float) -> np.ndarray:
    """Frame indices about `rate` per second apart, the first and the last always included."""
    if not (np.isfinite(rate) and rate > 0):
        raise HitogataError(f"sampling rate {rate!r}: allowed frames per second > 0")
    step = max(int(round(clip.rate / rate)), 1)
    return np.unique(np.append(np.arange(0, len(clip.times), step), len(clip.times) - 1))


def _measure(body: Body, vertices: np.ndarray, joints: np.ndarray) -> np.ndarray:
    v, posed = posture_arrays(body, vertices, joints)
    rest = JointSet(body.rig.names, body.rig.heads)
    m = measure_surface(v, body.faces, body_landmarks(body), rest, posed, tape_skin(body))
    return np.array([m.get(n) for n in NAMES])


def dynamic_ease(body: Body, motions: Mapping[str, MotionClip], surface: Surface | None = None,
                 rate: float = 5.0) -> list[MotionEase]:
    """`motion_ease` for each named motion."""
    if not motions:
        raise HitogataError("dynamic ease: no motions given")
    surface = surface or skinned_surface(body)
    return [motion_ease(body, name, clip, surface, rate) for name, clip in motions.items()]


def overall(results: list[MotionEase]) -> list[dict]:
    """Per measurement over all motions: the largest increase and decrease and the motion of each (None, with
    the reason in 'undefined', where the measurement has no meaning in a motion)."""
    rows = [r for e in results for r in e.largest()]
    out = []
    for name in NAMES:
        mine = [r for r in rows if r["measurement"] == name]
        defined = [r for r in mine if r["increase_cm"] is not None]
        why = "; ".join(f"{r['motion']}: {r['undefined']}" for r in mine if "undefined" in r)
        if name in HEIGHTS or not defined:
            out.append({"motion": "all", "measurement": name, "standing_cm": mine[0]["standing_cm"],
                        **{k: None for k in ("increase_cm", "increase_pct", "increase_in", "decrease_cm",
                                             "decrease_pct", "decrease_in")},
                        "undefined": UNDEFINED if name in HEIGHTS else why})
            continue
        up = max(defined, key=lambda r: r["increase_cm"])
        down = min(defined, key=lambda r: r["decrease_cm"])
        row = {"motion": "all", "measurement": name, "standing_cm": up["standing_cm"],
               "increase_cm": up["increase_cm"], "increase_pct": up["increase_pct"], "increase_in": up["motion"],
               "decrease_cm": down["decrease_cm"], "decrease_pct": down["decrease_pct"], "decrease_in": down["motion"]}
        if why:
            row["undefined"] = why
        out.append(row)
    return out


COLUMNS = ("motion", "measurement", "standing_cm", "increase_cm", "increase_pct", "increase_at_s", "increase_in",
           "decrease_cm", "decrease_pct", "decrease_at_s", "decrease_in", "undefined_because")


def ease_csv(results: list[MotionEase]) -> str:
    """One row per motion and measurement, then the 'all' rows; cm, %, s; 'undefined' in a cell that has no
    figure, and why in the last column (also where some frames had none)."""
    rows = [r for e in results for r in e.largest()] + overall(results)
    lines = [",".join(COLUMNS)]
    for r in rows:
        r = {**r, "undefined_because": _quoted(r.get("undefined", ""))}
        lines.append(",".join(_cell(r.get(c, "")) for c in COLUMNS))
    return "\n".join(lines) + "\n"


def _quoted(text: str) -> str:
    """A CSV field: quoted where it holds a comma or a quote."""
    return f'"{text.replace(chr(34), 2 * chr(34))}"' if ("," in text or '"' in text) else text


def ease_json(results: list[MotionEase]) -> str:
    """The same table as JSON, with the sampled series (cm) for plots."""
    heights = [NAMES.index(n) for n in HEIGHTS]
    doc = {"units": {"lengths": "cm", "times": "s"}, "measurements": list(NAMES),
           "undefined": {n: UNDEFINED if n in HEIGHTS else undefined_because(n) for n in NAMES
                         if n in HEIGHTS or any(not np.isfinite(e.values[:, NAMES.index(n)]).all() for e in results)},
           "motions": {e.motion: {"times_s": e.times.round(4).tolist(),
                                  "values_cm": [[None if k in heights or not np.isfinite(v) else v
                                                 for k, v in enumerate(row)]
                                                for row in (100 * e.values).round(3).tolist()],
                                  "standing_cm": (100 * e.standing).round(3).tolist(),
                                  "largest": e.largest()} for e in results},
           "all": overall(results)}
    return json.dumps(doc, indent=1)


def _cell(value) -> str:
    if value is None:
        return "undefined"
    return f"{value:.4g}" if isinstance(value, float) else str(value)
