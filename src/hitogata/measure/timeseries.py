"""Measurements and zone strains of a body over time, as CSV and as a plot.

The scenario code (dynamics) will produce a sequence of surfaces: times,
vertex arrays and joint centres. `measure_sequence` turns it into one row of
figures per frame; `write_series` writes them as CSV and as a plot (PNG).
"""

from __future__ import annotations

import io
import os
from dataclasses import dataclass
from pathlib import Path

import matplotlib
import numpy as np
from matplotlib.figure import Figure

from hitogata.body import Body
from hitogata.errors import HitogataError
from hitogata.export.atomic import write_bytes_atomically
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


def series_csv(series: MeasurementSeries) -> str:
    """One row per frame: time (s), each measurement (cm), each zone's stretch and area change (%)."""
    header = (
        ["time_s"]
        + [f"{name}_cm" for name in series.names]
        + [f"{zone}_stretch_pct" for zone in series.zones]
        + [f"{zone}_area_change_pct" for zone in series.zones]
    )
    table = np.column_stack([series.times, series.values * 100.0, series.zone_stretch, series.zone_area])
    lines = [",".join(header)] + [",".join(f"{x:.6g}" for x in row) for row in table]
    return "\n".join(lines) + "\n"


def series_plot(series: MeasurementSeries, title: str = "") -> bytes:
    """PNG: each measurement's change from the first frame (cm), and each zone's mean stretch (%),
    against time (changes, because stature and neck girth on one absolute axis would hide them)."""
    fig = Figure(figsize=(9, 8))
    top, bottom = fig.subplots(2, 1, sharex=True)
    colours = matplotlib.colormaps["tab20"].colors  # sixteen measurements: more than the default ten colours
    for k, name in enumerate(series.names):
        change = (series.values[:, k] - series.values[0, k]) * 100.0
        top.plot(series.times, change, label=name.replace("_", " "), color=colours[k % len(colours)])
    top.set_ylabel("change from first frame (cm)")
    top.legend(fontsize=7, ncol=3)
    top.grid(alpha=0.3)
    for k, zone in enumerate(series.zones):
        bottom.plot(series.times, series.zone_stretch[:, k], label=zone.replace("_", " "))
    bottom.set_ylabel("mean largest principal strain (%)")
    bottom.set_xlabel("time (s)")
    bottom.legend(fontsize=7, ncol=4)
    bottom.grid(alpha=0.3)
    if title:
        fig.suptitle(title)
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=100)
    return buffer.getvalue()


def write_series(series: MeasurementSeries, out_dir: str | os.PathLike, title: str = "") -> dict[str, Path]:
    """Write `measurements_over_time.csv` and `.png` into an existing directory, atomically."""
    out = Path(out_dir)
    if not out.is_dir():
        raise HitogataError(f"{out}: not a directory; allowed an existing directory for the time series")
    written = {"csv": out / "measurements_over_time.csv", "plot": out / "measurements_over_time.png"}
    write_bytes_atomically(written["csv"], series_csv(series).encode())
    write_bytes_atomically(written["plot"], series_plot(series, title))
    return written
