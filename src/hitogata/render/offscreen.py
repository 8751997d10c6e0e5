"""Render items from several views into RGB images, offscreen, with pyvista (VTK).

One VTK window serves all views of a call: the items are added once and the
camera moves; a `Renderer` keeps that window open from call to call (an
animation's frames: opening an EGL window and compiling its shaders costs
more than drawing a frame). Translucent items are sorted per pixel by depth peeling, which
needs multisampling off (with it, nested translucent surfaces silently
vanish); pyvista offers no FXAA with EGL, so edges are smoothed by
supersampling: rendering at twice the size and averaging.
"""

from __future__ import annotations

from collections.abc import Sequence
from types import ModuleType
from typing import TYPE_CHECKING, Self, TypeGuard

import numpy as np

from hitogata.errors import HitogataError
from hitogata.render.gl_check import ensure_offscreen_gl
from hitogata.render.scene import Color, Item, Layer, Lines, Points, rgb
from hitogata.render.shapes import capsules, spheres
from hitogata.render.views import View, frame_views, view

if TYPE_CHECKING:
    import pyvista

PEELS = 8  # translucent layers resolved per pixel
SPECULAR = 0.2
SUPERSAMPLE = 2  # render at twice the size and average 2 × 2 pixels: smooth edges
MAX_PIXELS = 4096  # per side of an image
LABEL_POINTS = 12  # label font size (at the final size)
LABEL_ROOM = 2.8  # pixels kept free at the top per point of label size
BAR_PIXELS = 64  # kept free at the bottom for a colour bar, its labels and title
BAR_POINTS = 10  # colour bar font size


def _pyvista() -> ModuleType:
    try:
        import pyvista
    except ImportError:
        raise HitogataError("rendering needs pyvista: pip install pyvista") from None
    return pyvista


def _polydata(pv: ModuleType, item: Item) -> pyvista.PolyData:
    """The item as a pyvista mesh: surfaces and capsules as triangles, thin lines and dots as such."""
    if isinstance(item, Layer):
        return pv.PolyData.from_regular_faces(item.vertices, item.faces)
    if isinstance(item, Lines):
        if item.radius is None:
            return pv.line_segments_from_points(item.segments.reshape(-1, 3))
        radii = np.asarray(item.radius, float)  # (S,) already: Lines.__post_init__ spreads one radius
        return pv.PolyData.from_regular_faces(*capsules(item.segments[:, 0], item.segments[:, 1], radii))
    if isinstance(item, Points):
        if item.radius is None:
            return pv.PolyData(item.points)
        radii = np.asarray(item.radius, float)  # (N,) already: Points.__post_init__ spreads one radius
        return pv.PolyData.from_regular_faces(*spheres(item.points, radii))
    raise HitogataError(f"render item {type(item).__name__}: allowed Layer, Lines or Points")


def _add(plotter: pyvista.Plotter, item: Item, mesh: pyvista.PolyData, scale: int) -> None:
    """Add one item's mesh with its style (pixel sizes times `scale`, the supersampling)."""
    common: dict[str, object] = {"opacity": item.opacity, "specular": SPECULAR, "render": False}  # drawn once, when all are in
    if isinstance(item, Layer) and not item.backfaces:
        common["culling"] = "back"
    if isinstance(item, Layer) and item.scalars is not None:
        where = "point" if len(item.scalars) == mesh.n_points else "cell"
        (mesh.point_data if where == "point" else mesh.cell_data)["values"] = item.scalars
        plotter.add_mesh(
            mesh,
            scalars="values",
            preference=where,
            cmap=item.colormap,
            clim=item.clim,
            smooth_shading=item.smooth,
            show_scalar_bar=item.scalar_title is not None,
            scalar_bar_args=_bar_style(item.scalar_title or "", plotter.window_size[1], scale),
            **common,
        )
        if item.scalar_title is not None:
            plotter.scalar_bars[item.scalar_title].SetTextPositionToPrecedeScalarBar()  # labels under the bar
    elif isinstance(item, Layer):
        plotter.add_mesh(mesh, color=rgb(item.color, "color"), smooth_shading=item.smooth, **common)
    elif isinstance(item, Lines) and item.radius is None:
        plotter.add_mesh(
            mesh, color=rgb(item.color, "color"), line_width=item.width * scale, opacity=item.opacity,
            render=False,
        )
    elif isinstance(item, Points) and item.radius is None:
        plotter.add_mesh(
            mesh,
            color=rgb(item.color, "color"),
            style="points",
            point_size=item.size * scale,
            render_points_as_spheres=True,
            opacity=item.opacity,
            render=False,
        )
    else:
        plotter.add_mesh(mesh, color=rgb(item.color, "color"), smooth_shading=True, **common)


def _bar_style(title: str, window_height: int, scale: int) -> dict:
    """A horizontal colour bar along the bottom, in the room kept free for it."""
    return {
        "title": title,
        "color": "black",
        "vertical": False,
        "position_x": 0.2,
        "position_y": 0.01,
        "width": 0.6,
        "height": (BAR_PIXELS * scale - 8) / window_height,
        "n_labels": 3,
        "fmt": "%.3g",
        "title_font_size": BAR_POINTS * scale,
        "label_font_size": BAR_POINTS * scale,
        "render": False,
    }


def _label(plotter: pyvista.Plotter, color: tuple[float, float, float], scale: int) -> pyvista.Text:
    """A text actor centred at the top of the picture; its text is set per view."""
    width, height = plotter.window_size
    points = LABEL_POINTS * scale
    actor = plotter.add_text(" ", position=(width / 2, height - points / 2), font_size=points, color=color,
                             render=False)
    actor.GetTextProperty().SetJustificationToCentered()
    actor.GetTextProperty().SetVerticalJustificationToTop()
    return actor


def _downsample(image: np.ndarray, scale: int) -> np.ndarray:
    """Average scale × scale blocks of an RGB image into one uint8 pixel."""
    h, w = image.shape[0] // scale, image.shape[1] // scale
    blocks = image[: h * scale, : w * scale].reshape(h, scale, w, scale, 3)
    n = scale * scale
    return ((blocks.sum(axis=(1, 3), dtype=np.uint32) + n // 2) // n).astype(np.uint8)  # rounded mean


def _size(size: Sequence[int | None]) -> tuple[int | None, int]:
    """(width or None, height), each 16..MAX_PIXELS."""

    def fits(s: object) -> TypeGuard[int | np.integer]:
        return isinstance(s, (int, np.integer)) and bool(16 <= s <= MAX_PIXELS)

    if len(size) != 2 or not (size[0] is None or fits(size[0])) or not fits(size[1]):
        raise HitogataError(
            f"size = {tuple(size)!r}: allowed (width, height) in pixels, 16..{MAX_PIXELS} each (width may be None)"
        )
    return (None if size[0] is None else int(size[0])), int(size[1])


class Renderer:
    """An offscreen window kept alive across pictures: `render(items, ...)` as `render_views`.

    Opening a VTK window on EGL and compiling its shaders costs more than
    drawing a frame; a sequence of pictures (an animation's frames) reuses
    one window, clearing its actors between calls and resizing it only when
    a picture's size changes. Use as a context manager, or `close()` it.
    """

    def __init__(self) -> None:
        self._plotter: pyvista.Plotter | None = None

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *_: object) -> None:
        self.close()

    def close(self) -> None:
        """Release the window (a later `render` opens a new one)."""
        if self._plotter is not None:
            self._plotter.close()
            self._plotter = None

    def _window(self, pv: ModuleType, size: tuple[int, int]) -> pyvista.Plotter:
        """The live plotter, cleared, at `size` pixels."""
        if self._plotter is None:
            self._plotter = pv.Plotter(off_screen=True, window_size=size)
            self._plotter.ren_win.SetMultiSamples(0)
        else:  # the last picture's actors and colour bars go; the lights stay (`clear()` would drop them)
            for title in list(self._plotter.scalar_bars.keys()):
                self._plotter.remove_scalar_bar(title, render=False)
            self._plotter.clear_actors()
            if tuple(self._plotter.window_size) != size:
                self._plotter.window_size = size
        return self._plotter

    def render(
        self,
        items: Sequence[Item],
        *,
        views: Sequence[str | View] = ("front", "side"),
        size: Sequence[int | None] = (600, 900),
        background: Color = "white",
        margin: float = 0.04,
        labels: bool = False,
        label_color: Color = "#333333",
        supersample: int = SUPERSAMPLE,
    ) -> list[np.ndarray]:
        """One (height, width, 3) uint8 RGB image per view of the items (see `render_views`).

        supersample: rendered at this many times the size and averaged down (1: no smoothing of
        edges, ~2.6x cheaper on software OpenGL; what an animation's small frames can afford)."""
        if supersample not in (1, 2, 3, 4):
            raise HitogataError(f"supersample = {supersample!r}: allowed 1, 2, 3 or 4")
        items = list(items)
        if not items:
            raise HitogataError("render_views: nothing to draw (give at least one Layer, Lines or Points)")
        cameras = [view(v) for v in views]
        if not cameras:
            raise HitogataError("render_views: views is empty; allowed names: front, side, back, right, top")
        width, height = _size(size)
        if not 0.0 <= margin < 1.0:
            raise HitogataError(f"margin = {margin!r}: allowed 0 ≤ margin < 1")
        background_rgb, text_rgb = rgb(background, "background"), rgb(label_color, "label_color")
        ensure_offscreen_gl()
        pv = _pyvista()
        meshes = [_polydata(pv, item) for item in items]
        top = LABEL_ROOM * LABEL_POINTS / height if labels else 0.0
        bars = any(isinstance(i, Layer) and i.scalars is not None and i.scalar_title is not None for i in items)
        bottom = BAR_PIXELS / height if bars else 0.0
        if top + bottom > 0.5:
            least = int(np.ceil(2 * (top + bottom) * height))
            raise HitogataError(
                f"size = {tuple(size)!r}: too low for the labels and colour bar; allowed height ≥ {least}")
        everything = np.vstack([m.points for m in meshes])
        framing = frame_views(everything, cameras, width / height if width else None, margin, top, bottom)
        widths = [
            int(np.clip(np.ceil(w / framing.half_height * height), 16, MAX_PIXELS)) if width is None else width
            for w in framing.half_widths
        ]
        window = max(widths)
        plotter = self._window(pv, (window * supersample, height * supersample))
        plotter.set_background(background_rgb)
        for item, mesh in zip(items, meshes):
            _add(plotter, item, mesh, supersample)
        peel = any(item.opacity < 1.0 for item in items)
        plotter.renderer.SetUseDepthPeeling(peel)
        if peel:
            plotter.renderer.SetMaximumNumberOfPeels(PEELS)
            plotter.renderer.SetOcclusionRatio(0.0)
        plotter.enable_parallel_projection()
        label = _label(plotter, text_rgb, supersample) if labels else None
        images = []
        for camera, keep, focal in zip(cameras, widths, framing.focal):
            _, up, direction = camera.axes()
            plotter.camera_position = [tuple(focal - framing.distance * direction), tuple(focal), tuple(up)]
            plotter.camera.parallel_scale = framing.half_height
            plotter.renderer.ResetCameraClippingRange()
            if label is not None:
                label.SetInput(camera.name)
            plotter.render()
            image = _downsample(np.asarray(plotter.screenshot(return_img=True))[..., :3], supersample)
            left = (window - keep) // 2
            images.append(image[:, left : left + keep])
        return images


def render_views(
    items: Sequence[Item],
    *,
    views: Sequence[str | View] = ("front", "side"),
    size: Sequence[int | None] = (600, 900),
    background: Color = "white",
    margin: float = 0.04,
    labels: bool = False,
    label_color: Color = "#333333",
) -> list[np.ndarray]:
    """One (height, width, 3) uint8 RGB image per view of the items (see `hitogata.render`).

    All views share one scale and centre fitted to the items with `margin`
    (a fraction) to spare; `labels` writes each view's name at its top.
    `size` is (width, height) in
    pixels; a width of None makes the height alone set the scale and each
    image as wide as its view's content (a side view of a standing body is
    narrower than its front view). For many pictures in a row, a `Renderer`
    keeps one window open.
    """
    with Renderer() as renderer:
        return renderer.render(items, views=views, size=size, background=background, margin=margin,
                               labels=labels, label_color=label_color)
