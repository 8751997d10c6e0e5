"""The interface pressure of a stretch garment by Laplace's law, at the leg's and trunk's levels.

A garment is given by its relaxed circumference at each level it covers, or
by one negative ease against the standing body's girths (−15 %: the garment
is 15 % smaller round than the body). On a body in any posture, at each
level: the girth C the fabric is stretched to (the tape girth: the fabric
bridges hollows), its strain ε = C / C₀ − 1, the fabric's tension T(ε) (N/m),
and the pressure P = T κ along the girth with κ the local curvature of the
fabric's path (`laplace.polygon_curvature`). The mean over the girth is the
equivalent circle's P = 2π T / C — what RAL-GZ 387-1 classifies at the ankle.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from hitogata.body.model import Body
from hitogata.errors import HitogataError
from hitogata.garment.fabric import Fabric
from hitogata.garment.laplace import WINDOW, CurvatureProfile, polygon_curvature
from hitogata.garment.levels import LEVELS, level_planes, level_tapes
from hitogata.measure.axes import JointSet
from hitogata.measure.measurements import posture_arrays

MMHG = 133.322387415  # Pa per mmHg (conventional millimetre of mercury)

# Medical compression stockings, pressure at the ankle (level B), mmHg: RAL-GZ 387/1
# (RAL Deutsches Institut für Gütesicherung und Kennzeichnung, "Medizinische
# Kompressionsstrümpfe", Gütesicherung RAL-GZ 387/1, 2008), classes I–IV.
COMPRESSION_CLASSES = (("I", 18.0, 21.0), ("II", 23.0, 32.0), ("III", 34.0, 46.0), ("IV", 49.0, np.inf))


@dataclass(frozen=True)
class Garment:
    """Relaxed circumferences (m) by level, or one ease (−0.15 = 15 % smaller than the standing body)."""

    relaxed: Mapping[str, float] | None = None
    ease: float | None = None
    levels: tuple[str, ...] = LEVELS

    def __post_init__(self) -> None:
        if (self.relaxed is None) == (self.ease is None):
            raise HitogataError("garment: give relaxed circumferences or an ease, not both or neither")
        unknown = [n for n in (self.relaxed or {}) if n not in LEVELS]
        if unknown:
            raise HitogataError(f"garment level {unknown[0]!r}: allowed {', '.join(LEVELS)}")
        bad = [(n, c) for n, c in (self.relaxed or {}).items() if not (np.isfinite(c) and 0.05 <= c <= 3.0)]
        if bad:
            raise HitogataError(f"garment level {bad[0][0]!r}: relaxed circumference {bad[0][1]!r} m; "
                                "allowed 0.05..3 m")
        if self.ease is not None and not (np.isfinite(self.ease) and -0.9 <= self.ease <= 1.0):
            raise HitogataError(f"garment ease {self.ease!r}: allowed -0.9..1 (e.g. -0.15 for 15 % negative ease)")

    @property
    def covered(self) -> tuple[str, ...]:
        return tuple(self.relaxed) if self.relaxed is not None else self.levels


@dataclass(frozen=True)
class LevelPressure:
    """One level: girth and relaxed circumference (m), strain, tension (N/m), the pressure
    along the girth (Pa, at `profile.points`), the equivalent circle's pressure (Pa)."""

    level: str
    girth: float
    relaxed: float
    strain: float
    tension: float
    profile: CurvatureProfile
    pressure: np.ndarray
    mean_pressure: float

    @property
    def peak_pressure(self) -> float:
        return float(self.pressure.max())

    def as_row(self) -> dict[str, float | str]:
        """The level's figures at the user's edge: cm, %, N/m, kPa and mmHg."""
        return {"level": self.level, "girth_cm": 100 * self.girth, "relaxed_cm": 100 * self.relaxed,
                "strain_pct": 100 * self.strain, "tension_N/m": self.tension,
                "mean_kPa": self.mean_pressure / 1000, "mean_mmHg": self.mean_pressure / MMHG,
                "peak_kPa": self.peak_pressure / 1000, "peak_mmHg": self.peak_pressure / MMHG}


def laplace_profile(path: np.ndarray, normal: np.ndarray, tension: float,
                    window: float = WINDOW) -> tuple[CurvatureProfile, np.ndarray]:
    """Pressure P = T κ (Pa) along a closed convex path (H, 3) in the plane with `normal`."""
    profile = polygon_curvature(path, normal, window)
    return profile, tension * np.maximum(profile.curvature, 0.0)


def garment_pressure(body: Body, garment: Garment, fabric: Fabric, vertices: np.ndarray | None = None,
                     joints: np.ndarray | None = None, window: float = WINDOW) -> dict[str, LevelPressure]:
    """Pressure at each level the garment covers, on the body at rest or in a posture
    (`vertices` (V, 3) and the rig's joint centres `joints`, as for `measure`)."""
    vertices, posed = posture_arrays(body, vertices, joints)
    tapes = level_tapes(body, vertices, posed)
    planes = level_planes(body, vertices, posed)
    standing = level_tapes(body, body.vertices, JointSet(body.rig.names, body.rig.heads)) \
        if garment.ease is not None else {}
    out = {}
    for level in garment.covered:
        tape = tapes[level]
        if not np.isfinite(tape.girth):
            raise HitogataError(f"garment level {level!r}: the body has no girth there in this posture")
        if garment.relaxed is not None:
            relaxed = garment.relaxed[level]
        elif garment.ease is not None:
            relaxed = (1.0 + garment.ease) * standing[level].girth
        else:  # Garment.__post_init__ already refuses this
            raise HitogataError("garment: give relaxed circumferences or an ease")
        strain = tape.girth / relaxed - 1.0
        tension = float(fabric.tension(strain))
        profile, pressure = laplace_profile(tape.path, planes[level][1], tension, window)
        out[level] = LevelPressure(level, tape.girth, relaxed, strain, tension, profile, pressure,
                                   2 * np.pi * tension / tape.girth)
    return out


def compression_class(ankle_pressure: float) -> str:
    """RAL-GZ 387/1 class of a stocking from its pressure at the ankle (Pa): 'I'…'IV', or
    'below class I' / 'between classes' where no class applies."""
    mmhg = ankle_pressure / MMHG
    for name, low, high in COMPRESSION_CLASSES:
        if low <= mmhg <= high:
            return name
    return "below class I" if mmhg < COMPRESSION_CLASSES[0][1] else "between classes"

