"""The dynamic-ease plots (PNG): reporting only, never imported by the computation."""

from __future__ import annotations

import io

import matplotlib
import numpy as np
from matplotlib.figure import Figure

from hitogata.garment.ease import HEIGHTS, NAMES, MotionEase


def ease_plot(results: list[MotionEase], title: str = "") -> bytes:
    """Per measurement, each motion's largest increase (right) and decrease (left) over standing, cm."""
    names = [n for n in NAMES if n not in HEIGHTS]
    fig = Figure(figsize=(9, 1.2 + 0.45 * len(names)))
    ax = fig.subplots()
    height = 0.8 / len(results)
    rows = np.arange(len(names))
    for k, e in enumerate(results):
        change = 100 * e.change[:, [NAMES.index(n) for n in names]]
        offset = rows - 0.4 + (k + 0.5) * height
        bars = ax.barh(offset, np.maximum(np.nanmax(change, axis=0), 0), height, label=e.motion.replace("_", " "))
        ax.barh(offset, np.minimum(np.nanmin(change, axis=0), 0), height, color=bars.patches[0].get_facecolor())
    ax.set_yticks(rows, [n.replace("_", " ") for n in names])
    ax.invert_yaxis()
    ax.axvline(0, color="black", linewidth=0.8)
    ax.set_xlabel("largest change from standing (cm): decrease ← → increase (the ease a woven garment needs)")
    ax.grid(axis="x", alpha=0.3)
    ax.legend(fontsize=7, loc="lower right")
    if title:
        ax.set_title(title)
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=100)
    return buffer.getvalue()


def ease_over_time(ease: MotionEase, title: str = "") -> bytes:
    """One motion: each girth's and length's change from standing (cm) against time."""
    names = [n for n in NAMES if n not in HEIGHTS]
    fig = Figure(figsize=(9, 4))
    ax = fig.subplots()
    colours = matplotlib.colormaps["tab20"].colors  # more measurements than the default ten colours
    for k, name in enumerate(names):
        ax.plot(ease.times, 100 * ease.change[:, NAMES.index(name)], marker=".", color=colours[k % len(colours)],
                label=name.replace("_", " "))
    ax.axhline(0, color="black", linewidth=0.8)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("change from standing (cm)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=2, loc="center left", bbox_to_anchor=(1.01, 0.5))
    ax.set_title(title or ease.motion.replace("_", " "))
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=100)
    return buffer.getvalue()
