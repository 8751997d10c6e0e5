"""A body's fit answers through a set of motions, and where a garment is most at risk.

One run of the garment computations over named motions — dynamic ease
(`garment.ease`), zone stretch (`garment.stretch`) and, for a stretch
garment, the pressure through each motion (`garment.pressure_motion`) — kept
together so that `hitogata ease` and `hitogata fit-report` share it. The
frames the report draws are chosen here too (`peak_frames`): per motion the
sampled frame where the garment zones stretch most and, with a garment, the
frame of the highest pressure. `risks` picks the headline numbers: the
largest ease need, the zone that must stretch most, the highest pressure.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from hitogata.body.model import Body
from hitogata.garment.ease import HEIGHTS, MotionEase, Surface, dynamic_ease, overall, sampled_frames
from hitogata.garment.fabric import Fabric
from hitogata.garment.pressure import MMHG, Garment
from hitogata.garment.pressure_motion import pressure_series
from hitogata.garment.stretch import PERCENTILE, ZoneStretch, area_percentile, stretch_table
from hitogata.measure.strain import skin_strain
from hitogata.motion.clip import MotionClip
from hitogata.posing.pose import poser_for
from hitogata.body.rig import posed_rig_heads
from hitogata.garment.stretch import garment_zones
from hitogata.geometry.normals import triangle_areas

PressureSeries = tuple[np.ndarray, dict[str, np.ndarray]]  # times (T,), per level (T, 3): strain, mean, peak Pa


@dataclass(frozen=True)
class FitAnswers:
    """Per motion (in the order given): the ease, the zone stretch, and the pressure when a garment is given."""

    body: Body
    clips: Mapping[str, MotionClip]
    surface: Surface
    rate: float
    ease: list[MotionEase]
    stretch: list[ZoneStretch]
    garment: tuple[Garment, Fabric] | None = None
    pressure: Mapping[str, PressureSeries] | None = None


def fit_answers(body: Body, clips: Mapping[str, MotionClip], surface: Surface, rate: float,
                garment: tuple[Garment, Fabric] | None = None) -> FitAnswers:
    """Ease, zone stretch and (with a garment and its fabric) pressure of `body` through each motion."""
    ease = dynamic_ease(body, clips, surface, rate)
    stretch = stretch_table(body, clips, surface, rate)
    pressure = None if garment is None else {
        name: pressure_series(body, *garment, clip, surface, rate) for name, clip in clips.items()}
    return FitAnswers(body, clips, surface, rate, ease, stretch, garment, pressure)


@dataclass(frozen=True)
class PeakFrames:
    """One motion's frames to draw (indices into its clip): the largest zone stretch, the highest pressure."""

    stretch: int
    pressure: int | None


def peak_frames(answers: FitAnswers, motion: str) -> PeakFrames:
    """The sampled frame whose garment zones stretch most (area-weighted 95th percentile of the principal
    strain over all zones' skin) and, with a garment, the frame of the highest peak pressure at any level."""
    body, clip = answers.body, answers.clips[motion]
    frames = sampled_frames(clip, answers.rate)
    zones, _ = garment_zones(body)
    faces = np.unique(np.concatenate(list(zones.values())))
    tri = body.vertices[body.faces[faces]]
    area = triangle_areas(tri)
    posed = answers.surface(clip.angles[frames], clip.root[frames])
    scores = []
    for v in posed:
        scores.append(area_percentile(skin_strain(body.vertices, v, body.faces[faces]).stretch_max, area, PERCENTILE))
    pressure = None
    if answers.pressure is not None:
        _, levels = answers.pressure[motion]
        peaks = np.max([rows[:, 2] for rows in levels.values()], axis=0)
        pressure = int(frames[int(np.argmax(peaks))])
    return PeakFrames(int(frames[int(np.argmax(scores))]), pressure)


def posture(answers: FitAnswers, motion: str, frame: int) -> tuple[np.ndarray, np.ndarray]:
    """The body's surface (V, 3) and rig joint centres at one frame of a motion (as `measure` takes them)."""
    clip, poser = answers.clips[motion], poser_for(answers.body)
    pose = poser.kinematics.pose(clip.angles[[frame]], root=clip.root[[frame]])
    vertices = answers.surface(clip.angles[[frame]], clip.root[[frame]])[0]
    return vertices, posed_rig_heads(answers.body.rig.heads, poser.skeleton.joints, pose.rotations[0],
                                     pose.translations[0])


def risks(answers: FitAnswers) -> dict[str, dict]:
    """The headline numbers (cm, %, s, mmHg): the largest ease need over the girths and lengths
    (heights left out: they change with the posture by definition; so is a girth undefined throughout), the zone needing the most
    stretch along a grain (lengthwise or crosswise), and with a garment the highest pressure."""
    rows = [r for r in overall(answers.ease) if r["measurement"] not in HEIGHTS and r["increase_cm"] is not None]
    ease = max(rows, key=lambda r: r["increase_cm"])
    at = next(r["increase_at_s"] for e in answers.ease if e.motion == ease["increase_in"] for r in e.largest()
              if r["measurement"] == ease["measurement"])
    out: dict[str, dict] = {"ease": {"measurement": ease["measurement"], "motion": ease["increase_in"],
                                     "standing_cm": ease["standing_cm"], "increase_cm": ease["increase_cm"],
                                     "increase_pct": ease["increase_pct"], "at_s": at}}
    zones = [(max(r["lengthwise_pct"], r["crosswise_pct"]), r) for z in answers.stretch for r in z.rows()]
    best, zone = max(zones, key=lambda item: item[0])
    out["stretch"] = {"zone": zone["zone"], "motion": zone["motion"], "stretch_pct": best,
                      "direction": "lengthwise" if zone["lengthwise_pct"] >= zone["crosswise_pct"] else "crosswise",
                      "lengthwise_pct": zone["lengthwise_pct"], "crosswise_pct": zone["crosswise_pct"],
                      "principal_pct": zone["principal_pct"]}
    if answers.pressure is not None:
        found = max(((rows[k, 2], motion, level, float(times[k]), rows[k])
                     for motion, (times, levels) in answers.pressure.items()
                     for level, rows in levels.items() for k in range(len(times))), key=lambda item: item[0])
        peak, motion, level, time, (strain, mean, _) = found
        out["pressure"] = {"level": level, "motion": motion, "at_s": time, "peak_mmHg": peak / MMHG,
                           "mean_mmHg": mean / MMHG, "strain_pct": 100 * strain}
    return out

