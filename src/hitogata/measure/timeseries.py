"""Measurements and zone strains of a body over time.

A simulation gives a sequence of surfaces: times, vertex arrays and joint
centres. `measure_sequence` turns it into one row of figures per frame
(`hitogata.report.series` writes them as CSV and as a plot).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.body.model import Body
from hitogata.errors import HitogataError
from hitogata.measure.axes import JointSet
from hitogata.measure.landmarks import body_landmarks
from hitogata.measure.measurements import MEASUREMENT_NAMES, check_names, measure_surface, posture_arrays, tape_skin
from hitogata.measure.strain import skin_strain
from hitogata.measure.zones import ZONE_NAMES, zone_strains


@dataclass(frozen=True)
class MeasurementSeries:
    """Figures per frame: measurements (T, M) in metres, zone strains (T, Z) in percent."""

    times: np.ndarray
    names: tuple[str, ...]
    values: np.ndarray
    zones: tuple[str, ...]
    zone_stretch: np.ndarray  # area-weighted mean largest principal strain, %
    zone_area: np.ndarray  # area change, %


def measure_sequence(
    body: Body,
    times: np.ndarray,
    vertices: np.ndarray,
    joints: np.ndarray,
    names: tuple[str, ...] = MEASUREMENT_NAMES,
) -> MeasurementSeries:
    """Measure every frame of a sequence: `times` (T,) s, `vertices` (T, V, 3), `joints` (T, B, 3) m."""
    check_names(names)
    times = np.asarray(times, dtype=np.float64)
    if times.ndim != 1 or not np.isfinite(times).all() or np.any(np.diff(times) <= 0):
        raise HitogataError(f"times: shape {times.shape}; allowed a 1-D, finite, increasing array of seconds")
    if len(vertices) != len(times) or len(joints) != len(times):
        raise HitogataError(
            f"sequence: {len(times)} times, {len(vertices)} vertex frames, {len(joints)} joint frames; "
            "allowed equal counts"
        )
    marks, rest, skin = body_landmarks(body), JointSet(body.rig.names, body.rig.heads), tape_skin(body)
    values = np.empty((len(times), len(names)))
    stretch = np.empty((len(times), len(ZONE_NAMES)))
    area = np.empty_like(stretch)
    for k, (frame, frame_joints) in enumerate(zip(vertices, joints)):
        v, posed = posture_arrays(body, frame, frame_joints)
        m = measure_surface(v, body.faces, marks, rest, posed, skin)
        values[k] = [m.get(name) for name in names]
        zones = zone_strains(body, skin_strain(body.vertices, v, body.faces))
        stretch[k] = [zones[z].stretch_mean for z in ZONE_NAMES]
        area[k] = [zones[z].area_change for z in ZONE_NAMES]
    return MeasurementSeries(times, tuple(names), values, ZONE_NAMES, stretch, area)
