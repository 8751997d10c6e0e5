"""A garment's pressure through a motion: its levels' strain, mean and peak pressure frame by frame."""

from __future__ import annotations

import numpy as np

from hitogata.body.model import Body
from hitogata.garment.ease import Surface, sampled_frames, skinned_surface
from hitogata.garment.fabric import Fabric
from hitogata.garment.pressure import MMHG, Garment, garment_pressure
from hitogata.body.rig import posed_rig_heads
from hitogata.motion.clip import MotionClip
from hitogata.posing.pose import poser_for


def pressure_series(body: Body, garment: Garment, fabric: Fabric, clip: MotionClip, surface: Surface | None = None,
                    rate: float = 5.0) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """The pressure through a motion (a `motion.clip.MotionClip`), sampled at `rate` frames per second:
    times (T,) and, per level, (T, 3) rows of strain, mean and peak pressure (Pa)."""
    surface = surface or skinned_surface(body)
    frames = sampled_frames(clip, rate)
    poser = poser_for(body)
    pose = poser.kinematics.pose(clip.angles[frames], root=clip.root[frames])
    vertices = surface(clip.angles[frames], clip.root[frames])
    out = {level: np.empty((len(frames), 3)) for level in garment.covered}
    for k in range(len(frames)):
        joints = posed_rig_heads(body.rig.heads, poser.skeleton.joints, pose.rotations[k], pose.translations[k])
        for level, result in garment_pressure(body, garment, fabric, vertices[k], joints).items():
            out[level][k] = (result.strain, result.mean_pressure, result.peak_pressure)
    return clip.times[frames], out


def pressure_csv(series: dict[str, tuple[np.ndarray, dict[str, np.ndarray]]]) -> str:
    """One row per motion, frame and level: time (s), strain (%), mean and peak pressure (kPa and mmHg)."""
    lines = ["motion,time_s,level,strain_pct,mean_kPa,mean_mmHg,peak_kPa,peak_mmHg"]
    for motion, (times, levels) in series.items():
        for k, t in enumerate(times):
            for level, rows in levels.items():
                e, mean, peak = rows[k]
                lines.append(f"{motion},{t:.4g},{level},{100 * e:.4g},{mean / 1000:.4g},{mean / MMHG:.4g},"
                             f"{peak / 1000:.4g},{peak / MMHG:.4g}")
    return "\n".join(lines) + "\n"
