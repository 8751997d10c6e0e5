"""Pictures of a study's percentile tables: per motion, each girth's and length's dynamic ease and
each zone's required stretch as P5–P95 bands with the median, one colour per size or body cluster.

Reporting only: the computation (tasks, runner) never imports this module.
"""

from __future__ import annotations

import io
import os
from pathlib import Path

import matplotlib
from matplotlib.figure import Figure

from hitogata.export.atomic import write_bytes_atomically
from hitogata.study.results import Band

PANELS = (("dynamic_ease", "dynamic ease: largest increase over standing (cm)", ("girth", "length")),
          ("required_stretch", "required stretch: largest P95 skin stretch (%)", ("zone",)))


def motion_plot(bands: list[Band], motion: str, title: str = "") -> bytes:
    """PNG: the bands of one motion, one panel for ease and one for stretch."""
    fig = Figure(figsize=(11, 6))
    axes = fig.subplots(1, 2)
    chosen = [b for b in bands if b.motion == motion]
    groups = list(dict.fromkeys(b.group for b in chosen))
    colours = matplotlib.colormaps["tab10"].colors
    for ax, (quantity, label, kinds) in zip(axes, PANELS):
        lines = [b for b in chosen if b.quantity == quantity and b.kind in kinds]
        names = list(dict.fromkeys(b.name for b in lines))
        height = 0.8 / max(len(groups), 1)
        for g, group in enumerate(groups):
            mine = {b.name: b for b in lines if b.group == group}
            ys = [k + (g - (len(groups) - 1) / 2) * height for k, name in enumerate(names) if name in mine]
            found = [mine[name] for name in names if name in mine]
            colour = "black" if group == "all" else colours[g % len(colours)]
            ax.hlines(ys, [b.p5 for b in found], [b.p95 for b in found], color=colour, linewidth=3, alpha=0.6,
                      label=f"{group} (P5–P95, ● P50)")
            ax.plot([b.p50 for b in found], ys, "o", color=colour, markersize=4)
        ax.set_yticks(range(len(names)), [n.replace("_", " ") for n in names], fontsize=8)
        ax.invert_yaxis()
        ax.axvline(0.0, color="grey", linewidth=0.8)
        ax.set_xlabel(label)
        ax.grid(axis="x", alpha=0.3)
    axes[0].legend(fontsize=7, loc="lower right")
    fig.suptitle(f"{title}: {motion}" if title else motion)
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=100)
    return buffer.getvalue()


def write_plots(bands: list[Band], out: str | os.PathLike, title: str = "") -> list[Path]:
    """`bands_<motion>.png` per motion in the results folder, atomically."""
    motions = list(dict.fromkeys(b.motion for b in bands))
    return [write_bytes_atomically(Path(out) / f"bands_{m}.png", motion_plot(bands, m, title)) for m in motions]
