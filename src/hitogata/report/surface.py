"""Orthographic pictures of a body surface with matplotlib, front and back.

Faces are drawn into an image with a depth buffer (`raster`), coloured by a
value per face (e.g. skin stretch) and shaded by their tilt to the viewer so
the shape reads; matplotlib places the views, lines, labels and colour bar.
Figures are made without pyplot, so importing this module changes no
matplotlib backend.
"""

from __future__ import annotations

import io
from collections.abc import Mapping
from dataclasses import dataclass

import matplotlib
import numpy as np
from matplotlib.cm import ScalarMappable
from matplotlib.collections import LineCollection
from matplotlib.colors import Colormap, Normalize
from matplotlib.figure import Figure

from hitogata.report.raster import rasterise

# View name → (screen-right axis, viewing direction towards the body), body frame. The names
# mean what they mean in `hitogata.render.views`: "side" shows the body's left side (its front
# on the picture's left), "right" its right side.
VIEWS = {
    "front": (np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, -1.0])),
    "back": (np.array([-1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])),
    "side": (np.array([0.0, 0.0, -1.0]), np.array([-1.0, 0.0, 0.0])),  # from the body's left
    "right": (np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])),  # from the body's right
}


@dataclass(frozen=True)
class Colouring:
    """Face values with the colour map and range that turn them into colours."""

    values: np.ndarray  # (F,)
    cmap: str | Colormap
    norm: Normalize
    label: str


PIXEL = 0.0025  # m per pixel of the faces' image: a little finer than the saved picture's (~3.2 mm)
DPI = 110


def draw_view(ax, vertices: np.ndarray, faces: np.ndarray, view: str, colouring: Colouring | None) -> None:
    """Draw one orthographic view of the surface into `ax`."""
    right, looking = VIEWS[view]
    up = np.array([0.0, 1.0, 0.0])
    tri = vertices[faces]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-300)
    facing = -(normals @ looking)
    kept = np.flatnonzero(facing > 0.0)
    screen = np.stack([tri[kept] @ right, tri[kept] @ up], axis=2)
    if colouring is None:
        base = np.tile(np.array([0.85, 0.72, 0.62, 1.0]), (len(kept), 1))
    else:
        cmap = matplotlib.colormaps[colouring.cmap] if isinstance(colouring.cmap, str) else colouring.cmap
        base = cmap(colouring.norm(colouring.values[kept]))
    shade = 0.45 + 0.55 * facing[kept][:, None]
    colours = base.copy()
    colours[:, :3] *= shade
    image = rasterise(screen, tri[kept] @ looking, colours, PIXEL)
    ax.imshow(image.rgba, extent=image.extent, origin="lower", interpolation="antialiased")
    ax.set_xlim(screen[..., 0].min(), screen[..., 0].max())
    ax.set_ylim(screen[..., 1].min(), screen[..., 1].max())
    ax.set_aspect("equal")
    ax.set_title(view, y=1.0)  # placed, so drawing does not measure the (hidden) axes for it
    ax.axis("off")


def render_png(
    vertices: np.ndarray,
    faces: np.ndarray,
    views: tuple[str, ...],
    colouring: Colouring | None = None,
    title: str = "",
    overlays: Mapping[str, np.ndarray] | tuple[np.ndarray, ...] = (),
) -> bytes:
    """PNG bytes showing the surface from each view, with optional polylines drawn on top.

    Named overlays (a mapping) are labelled in the first view, each at its end
    furthest to the viewer's right, so a tape line says which measurement it is.
    """
    named = overlays if isinstance(overlays, Mapping) else {}
    lines = list(overlays.values()) if isinstance(overlays, Mapping) else list(overlays)
    fig = Figure(figsize=(3.2 * len(views) + (1.2 if colouring else 0), 6.4))
    axes = np.atleast_1d(fig.subplots(1, len(views)))
    for ax, view in zip(axes, views):
        draw_view(ax, vertices, faces, view, colouring)
        right, _ = VIEWS[view]
        ax.add_collection(LineCollection([np.stack([line @ right, line[:, 1]], axis=1) for line in lines],
                                         linewidths=1.0, colors="k"))
    if named:
        _label_lines(axes[0], named, VIEWS[views[0]][0])
    _same_scale(axes)
    if colouring is not None:
        mappable = ScalarMappable(norm=colouring.norm, cmap=colouring.cmap)
        fig.colorbar(mappable, ax=list(axes), shrink=0.7, label=colouring.label)
    if title:
        fig.suptitle(title)
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=DPI)
    return buffer.getvalue()


GAP = 0.055  # m: the least height between two labels


def _label_lines(ax, lines: Mapping[str, np.ndarray], right: np.ndarray) -> None:
    """Each line's name in a column right of the body, a leader to the line's rightmost point, spread apart."""
    column = ax.get_xlim()[1] + 0.02
    used: list[float] = []
    leaders = []
    for name, line in sorted(lines.items(), key=lambda item: -float(item[1][:, 1].max())):
        x = line @ right
        k = int(np.argmax(x))
        y = float(line[k, 1])
        y = min([y, *(u - GAP for u in used if u - y < GAP)])  # below the label above, if too close
        used.append(y)
        leaders.append([(float(x[k]), float(line[k, 1])), (column, y)])
        ax.text(column, y, name.replace("_", " "), fontsize=6, color="k", va="center", ha="left", clip_on=False)
    ax.add_collection(LineCollection(leaders, linewidths=0.4, colors="0.45", clip_on=False))


def _same_scale(axes) -> None:
    """Give every view the same metres per inch: the widest extents, each view centred."""
    half_x = max(np.ptp(ax.get_xlim()) for ax in axes) / 2 + 0.05
    y_lo = min(ax.get_ylim()[0] for ax in axes) - 0.03
    y_hi = max(ax.get_ylim()[1] for ax in axes) + 0.03
    for ax in axes:
        centre = float(np.mean(ax.get_xlim()))
        ax.set_xlim(centre - half_x, centre + half_x)
        ax.set_ylim(y_lo, y_hi)
