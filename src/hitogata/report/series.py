"""A measurement series over time as a CSV table and a plot (PNG), written atomically."""

from __future__ import annotations

import io
import os
from pathlib import Path

import matplotlib
import numpy as np
from matplotlib.figure import Figure

from hitogata.errors import HitogataError
from hitogata.export.atomic import write_bytes_atomically
from hitogata.measure.timeseries import MeasurementSeries


def series_csv(series: MeasurementSeries) -> str:
    """One row per frame: time (s), each measurement (cm), each zone's stretch and area change (%); 'undefined'
    where a frame has none (the knee girth in deep flexion)."""
    header = (
        ["time_s"]
        + [f"{name}_cm" for name in series.names]
        + [f"{zone}_stretch_pct" for zone in series.zones]
        + [f"{zone}_area_change_pct" for zone in series.zones]
    )
    table = np.column_stack([series.times, series.values * 100.0, series.zone_stretch, series.zone_area])
    lines = [",".join(header)] + [",".join(f"{x:.6g}" if np.isfinite(x) else "undefined" for x in row)
                                  for row in table]
    return "\n".join(lines) + "\n"


def series_plot(series: MeasurementSeries, title: str = "") -> bytes:
    """PNG: each measurement's change from the first frame (cm), and each zone's mean stretch (%),
    against time (changes, because stature and neck girth on one absolute axis would hide them)."""
    fig = Figure(figsize=(9, 8))
    top, bottom = fig.subplots(2, 1, sharex=True)
    colours = matplotlib.colormaps["tab20"].colors  # 27 measurements: twenty colours, then dashed lines
    for k, name in enumerate(series.names):
        change = (series.values[:, k] - series.values[0, k]) * 100.0
        top.plot(series.times, change, label=name.replace("_", " "), color=colours[k % len(colours)],
                 linestyle="-" if k < len(colours) else "--")
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
