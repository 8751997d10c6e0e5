"""The garment's pressure everywhere it covers: sections every centimetre between its levels.

Between two neighbouring levels the garment goes round planes interpolated
from theirs (origin, normal, centre: linearly; the part's skin: the nearer
level's), its relaxed circumference interpolated too — or, for a garment
given by an ease, that ease against the standing body's girth of the same
section. Each section's pressure profile (`pressure.laplace_profile`) is
sampled along the fabric's path; a skin vertex takes the pressure of the
nearest sample within REACH, and has none (NaN) where no sample is that near:
outside the garment, or in a hollow the fabric bridges.

Mapped spans: ankle → calf → knee → thigh (a stocking) and hip → waist (a
girdle, a waistband). The thigh → hip span is not: between the top of the
thigh and the seat no single girth goes round one part (the crotch).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from hitogata.body.model import Body
from hitogata.errors import HitogataError
from hitogata.garment.fabric import Fabric
from hitogata.garment.laplace import WINDOW
from hitogata.garment.levels import level_planes
from hitogata.garment.pressure import Garment, laplace_profile
from hitogata.measure.axes import JointSet
from hitogata.measure.measurements import posture_arrays
from hitogata.measure.sections import tape_girth
from hitogata.geometry.topology import topology

SPANS = (("ankle", "calf"), ("calf", "knee"), ("knee", "thigh"), ("hip", "waist"))
SPACING = 0.01  # m between sections
REACH = 0.01  # m: a vertex this near a sample of the fabric's path is pressed by it


@dataclass(frozen=True)
class PressureMap:
    """Pressure (V,) Pa on the skin (NaN: not covered or not touched), and per section its
    span, fraction, girth (m), strain and tension (N/m)."""

    pressure: np.ndarray
    sections: list[dict]


def pressure_map(body: Body, garment: Garment, fabric: Fabric, vertices: np.ndarray | None = None,
                 joints: np.ndarray | None = None, spacing: float = SPACING,
                 window: float = WINDOW) -> PressureMap:
    """The pressure on every skin vertex the garment covers, at rest or in a posture."""
    vertices, posed = posture_arrays(body, vertices, joints)
    rest = JointSet(body.rig.names, body.rig.heads)
    planes = level_planes(body, vertices, posed)
    standing = level_planes(body, body.vertices, rest) if garment.ease is not None else None
    topo = topology(body.faces)
    covered = set(garment.covered)
    points, pressures, sections = [], [], []
    for low, high in SPANS:
        if low not in covered or high not in covered:
            continue
        a, b = planes[low], planes[high]
        count = max(int(np.ceil(np.linalg.norm(b[0] - a[0]) / spacing)), 1)
        for s in np.linspace(0.0, 1.0, count + 1):
            tape, normal = _tape(vertices, topo, a, b, s)
            if not np.isfinite(tape.girth):
                continue
            if garment.relaxed is not None:
                relaxed = (1 - s) * garment.relaxed[low] + s * garment.relaxed[high]
            elif garment.ease is not None and standing is not None:
                relaxed = (1.0 + garment.ease) * _tape(body.vertices, topo, standing[low], standing[high], s)[0].girth
            else:  # Garment.__post_init__ already refuses this
                raise HitogataError("garment: give relaxed circumferences or an ease")
            strain = tape.girth / relaxed - 1.0
            tension = float(fabric.tension(strain))
            profile, pressure = laplace_profile(tape.path, normal, tension, window)
            points.append(profile.points)
            pressures.append(pressure)
            sections.append({"span": f"{low}-{high}", "fraction": float(s), "girth": tape.girth, "strain": strain,
                             "tension": tension})
    out = np.full(len(vertices), np.nan)
    if points:
        distance, nearest = cKDTree(np.vstack(points)).query(vertices, distance_upper_bound=REACH)
        touched = np.isfinite(distance)
        out[touched] = np.concatenate(pressures)[nearest[touched]]
    return PressureMap(out, sections)


def _tape(vertices: np.ndarray, topo, a, b, s: float):
    origin = (1 - s) * a[0] + s * b[0]
    normal = (1 - s) * a[1] + s * b[1]
    normal = normal / np.linalg.norm(normal)
    centre = (1 - s) * a[2] + s * b[2]
    skin = a[3] if s < 0.5 else b[3]
    return tape_girth(vertices, topo, origin, normal, centre, part=skin), normal
