"""Orthographic pictures of a body surface, front and back, drawn with numpy and Pillow.

Faces are drawn into an image with a depth buffer (`raster`), coloured by a
value per face (e.g. skin stretch) and shaded by their tilt to the viewer so
the shape reads; lines (tapes) are drawn on a finer layer and reduced, so
they are smooth. Every view has the same scale. The layout follows
matplotlib's defaults without importing matplotlib, which takes longer to
load than the whole picture takes to draw
(docs/decisions/0017-pictures-without-matplotlib.md); only a colour map
(the strain heat map's) is looked up in matplotlib.
"""

from __future__ import annotations

import importlib.util
import io
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from hitogata.report.raster import Raster, rasterise
from hitogata.geometry.normals import triangle_normals

if TYPE_CHECKING:
    from matplotlib.colors import Colormap, Normalize

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
    norm: Normalize  # values → 0..1 along the colour map
    label: str


DPI = 110
PANEL = 3.2  # in: the width of one view
HEIGHT = 6.4  # in
BAR = 1.2  # in: added for the colour bar
LEFT, RIGHT, BOTTOM, TOP, WSPACE = 0.125, 0.9, 0.11, 0.88, 0.2  # the views' area (matplotlib's subplots)
BAR_SHARE, BAR_PAD = 0.2, 0.05  # of the views' area: the colour bar's room and its gap (matplotlib's)
SKIN = (0.85, 0.72, 0.62, 1.0)
LINE_WIDTH, LEADER_WIDTH, LEADER_GREY = 1.0, 0.4, 115  # pt, pt, 0..255
TITLE_SIZE, LABEL_SIZE, TICK_SIZE = 12.0, 6.0, 10.0  # pt
FINE = 3  # lines are drawn this many times finer, then reduced: smooth edges
GAP = 0.055  # m: the least height between two labels


@dataclass(frozen=True)
class ViewFaces:
    """The faces turned towards one view, on the screen (x right, y up) with their depth and colours."""

    screen: np.ndarray  # (K, 3, 2) m
    depth: np.ndarray  # (K, 3) m, larger is farther
    colours: np.ndarray  # (K, 4) RGBA 0..1, shaded


def view_faces(vertices: np.ndarray, faces: np.ndarray, view: str, colouring: Colouring | None) -> ViewFaces:
    """The surface's faces seen from `view`, coloured and shaded by their tilt to the viewer."""
    right, looking = VIEWS[view]
    up = np.array([0.0, 1.0, 0.0])
    tri = vertices[faces]
    normals = triangle_normals(tri)
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-300)
    facing = -(normals @ looking)
    kept = np.flatnonzero(facing > 0.0)
    if colouring is None:
        base = np.tile(np.array(SKIN), (len(kept), 1))
    else:
        base = _colour_map(colouring.cmap)(colouring.norm(colouring.values[kept]))
    colours = np.array(base, dtype=float)
    colours[:, :3] *= 0.45 + 0.55 * facing[kept][:, None]
    return ViewFaces(np.stack([tri[kept] @ right, tri[kept] @ up], axis=2), tri[kept] @ looking, colours)


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
    width, height = round((PANEL * len(views) + (BAR if colouring else 0.0)) * DPI), round(HEIGHT * DPI)
    canvas = Image.new("RGBA", (width, height), "white")
    fine = Image.new("RGBA", (width * FINE, height * FINE), (0, 0, 0, 0))
    pen, text = ImageDraw.Draw(fine), ImageDraw.Draw(canvas)
    seen = [view_faces(vertices, faces, view, colouring) for view in views]
    area = (LEFT * width, (RIGHT - (BAR_SHARE if colouring else 0.0) * (RIGHT - LEFT)) * width)
    panel = (area[1] - area[0]) / (len(views) + WSPACE * (len(views) - 1))
    tall = (TOP - BOTTOM) * height
    half_x = max(float(np.ptp(f.screen[..., 0])) for f in seen) / 2 + 0.05  # every view at the same scale
    y_lo = min(float(f.screen[..., 1].min()) for f in seen) - 0.03
    y_hi = max(float(f.screen[..., 1].max()) for f in seen) + 0.03
    scale = max(2 * half_x / panel, (y_hi - y_lo) / tall)  # m per pixel
    middle_y = (1 - (TOP + BOTTOM) / 2) * height
    for k, (view, shown) in enumerate(zip(views, seen)):
        x = shown.screen[..., 0]
        middle_x = area[0] + (k + 0.5) * panel + k * WSPACE * panel
        image = rasterise(shown.screen, shown.depth, shown.colours, scale)
        place = _Placement.of(image, scale, middle_x - (0.5 * (x.min() + x.max()) - image.extent[0]) / scale,
                              middle_y - (image.extent[3] - 0.5 * (y_lo + y_hi)) / scale)
        canvas.alpha_composite(_image(image), (place.left, place.top))
        right = VIEWS[view][0]
        for line in lines:
            pen.line(place.fine(line @ right, line[:, 1]), fill="black", width=_px(LINE_WIDTH * FINE), joint="curve")
        text.text((middle_x, place.point(0.0, y_hi)[1] - 6), view, fill="black", font=_font(TITLE_SIZE), anchor="md")
        if named and k == 0:
            _label_lines(named, right, float(x.max()) + 0.02, place, pen, text)
    canvas.alpha_composite(fine.reduce(FINE))
    if colouring is not None:
        _colour_bar(canvas, colouring, area[1] + BAR_PAD * (RIGHT - LEFT) * width, middle_y, 0.7 * tall)
    if title:
        text.text((width / 2, 0.02 * height), title, fill="black", font=_font(TITLE_SIZE), anchor="mt")
    buffer = io.BytesIO()
    canvas.convert("RGB").save(buffer, format="png")
    return buffer.getvalue()


@dataclass(frozen=True)
class _Placement:
    """Where a view's image sits on the canvas: screen metres → canvas pixels (and the fine layer's)."""

    left: int
    top: int
    extent: tuple[float, float, float, float]  # the image's, m
    scale: float  # m per pixel

    @classmethod
    def of(cls, image: Raster, scale: float, left: float, top: float) -> _Placement:
        return cls(round(left), round(top), image.extent, scale)

    def pixels(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Canvas columns and rows of screen points (m)."""
        return self.left + (x - self.extent[0]) / self.scale, self.top + (self.extent[3] - y) / self.scale

    def point(self, x: float, y: float) -> tuple[float, float]:
        column, row = self.pixels(np.array(x), np.array(y))
        return float(column), float(row)

    def fine(self, x: np.ndarray, y: np.ndarray) -> list[tuple[float, float]]:
        """A polyline's points on the fine layer."""
        columns, rows = self.pixels(x, y)
        return list(zip((FINE * columns).tolist(), (FINE * rows).tolist()))


def _image(raster: Raster) -> Image.Image:
    """The raster as a Pillow image, top row first."""
    return Image.fromarray(np.round(255 * raster.rgba[::-1]).astype(np.uint8), "RGBA")


def _px(points: float) -> int:
    """Whole pixels of a width given in points (at least one)."""
    return max(1, round(points * DPI / 72))


@cache
def _font(points: float) -> ImageFont.FreeTypeFont | ImageFont.ImageFont:
    """DejaVu Sans (matplotlib ships it; found without importing matplotlib) at a size in points."""
    spec = importlib.util.find_spec("matplotlib")
    for folder in (spec.submodule_search_locations or []) if spec else []:
        path = Path(folder) / "mpl-data" / "fonts" / "ttf" / "DejaVuSans.ttf"
        if path.is_file():
            return ImageFont.truetype(str(path), points * DPI / 72)
    return ImageFont.load_default(points * DPI / 72)


def _colour_map(cmap: str | Colormap) -> Colormap:
    import matplotlib

    return matplotlib.colormaps[cmap] if isinstance(cmap, str) else cmap


def _label_lines(lines: Mapping[str, np.ndarray], right: np.ndarray, column: float, place: _Placement,
                 pen: ImageDraw.ImageDraw, text: ImageDraw.ImageDraw) -> None:
    """Each line's name in a column right of the body (at `column`, m), a leader to the line's
    rightmost point, the names spread apart."""
    used: list[float] = []
    for name, line in sorted(lines.items(), key=lambda item: -float(item[1][:, 1].max())):
        x = line @ right
        k = int(np.argmax(x))
        y = min([float(line[k, 1]), *(u - GAP for u in used if u - float(line[k, 1]) < GAP)])  # below the one above
        used.append(y)
        pen.line(place.fine(np.array([x[k], column]), np.array([line[k, 1], y])), fill=(LEADER_GREY,) * 3,
                 width=_px(LEADER_WIDTH * FINE))
        text.text(place.point(column, y), name.replace("_", " "), fill="black",
                  font=_font(LABEL_SIZE), anchor="lm")


def _colour_bar(canvas: Image.Image, colouring: Colouring, left: float, middle: float, tall: float) -> None:
    """A vertical colour bar of `tall` pixels with ticks at round values and the colouring's label."""
    width, top = round(0.05 * tall), round(middle - tall / 2)
    strip = _colour_map(colouring.cmap)(np.linspace(1.0, 0.0, round(tall)))[:, None, :3]  # top: the largest
    canvas.paste(Image.fromarray(np.round(255 * np.repeat(strip, width, axis=1)).astype(np.uint8), "RGB"),
                 (round(left), top))
    draw = ImageDraw.Draw(canvas)
    draw.rectangle((round(left), top, round(left) + width, top + round(tall)), outline="black")
    lo, hi = float(colouring.norm.vmin), float(colouring.norm.vmax)
    step = _round_step(hi - lo)
    widest = 0.0
    for value in np.arange(np.ceil(lo / step), np.floor(hi / step) + 0.5) * step:  # within the bar
        row = top + (1.0 - float(colouring.norm(value))) * tall
        draw.line((round(left) + width, row, round(left) + width + 4, row), fill="black")
        label = f"{value:g}".replace("-", "\u2212")
        draw.text((round(left) + width + 7, row), label, fill="black", font=_font(TICK_SIZE), anchor="lm")
        widest = max(widest, draw.textlength(label, font=_font(TICK_SIZE)))
    name = Image.new("RGBA", (round(tall) + 200, _px(TICK_SIZE) * 2), (255, 255, 255, 0))
    ImageDraw.Draw(name).text((name.width / 2, name.height / 2), colouring.label, fill="black",
                              font=_font(TICK_SIZE), anchor="mm")
    name = name.rotate(90, expand=True)
    canvas.alpha_composite(name, (round(left + width + 12 + widest), round(middle - name.height / 2)))


def _round_step(span: float) -> float:
    """A step of 1, 2 or 5 times a power of ten giving four to ten ticks over `span`."""
    power = 10.0 ** np.floor(np.log10(span / 4))
    return float(next(m * power for m in (1, 2, 5, 10) if span / (m * power) <= 10))
