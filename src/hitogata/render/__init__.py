"""The project's offscreen 3D renderer: pictures of bodies, skeletons and FEM results.

Describe what to draw as plain data, render it from named views, save PNGs::

    from hitogata.render import Layer, Lines, Points, render_views, save_png, side_by_side

    skin = Layer(body.vertices, body.faces, color="#d9b59c", opacity=0.35)
    bones = Lines(segments, color="#f2efe6", radius=0.008)        # (S, 2, 3) → capsules
    joints = Points(centres, color="#c0392b", radius=0.012)       # (N, 3) → spheres
    front, side = render_views([bones, joints, skin], views=("front", "side"), size=(600, 900))
    save_png("figure.png", side_by_side([front, side]))

- `Layer(vertices, faces, color, opacity, scalars, colormap, clim, scalar_title, smooth)`:
  a triangle surface; opacity < 1 is translucent (nested surfaces show through);
  `scalars` per vertex (V,) or per face (F,) colour it (e.g. a mode shape's
  displacement), `scalar_title` adds a colour bar.
- `Lines(segments, color, width, radius, opacity)`: segments (S, 2, 3), `width`
  pixels wide, or capsules of `radius` metres (a number or one per segment).
- `Points(points, color, size, radius, opacity)`: dots `size` pixels across, or
  spheres of `radius` metres.
- `render_views(items, *, views=("front", "side"), size=(600, 900), background="white",
  margin=0.04, labels=False, label_color="#333333") -> list[np.ndarray]`: one (H, W, 3)
  uint8 RGB image per view, all at one scale and centre (orthographic), so views line
  up; `size=(None, H)` lets the height set the scale and each view be as wide as it
  needs; `labels` writes each view's name at its top.
- Views (body frame: +Y up, +Z front, +X the body's left): "front" looks along −Z,
  "side" shows the body's left side (front on the picture's left), "back",
  "right", "top"; or any `View(name, direction, up)`.
- `Renderer()`: `render(items, ..., supersample=2)` as `render_views`, keeping one
  window open from call to call (an animation's frames); close it or use `with`.
  `supersample=1` skips the edge smoothing (~2.6x cheaper on software OpenGL).
- `side_by_side(images, gap, background)`, `titled(image, title)` (a band with a
  centred title on top), `save_png(path, image)` (atomic), `png_bytes(image)`.
- `hitogata.render.figures.skeleton_items(posed, skin=, muscles=, other_muscles=)`:
  the items of the paper's Fig. 3(a) for a `PosedBody`.

Rendering runs without a display through Mesa's EGL (software OpenGL);
`ensure_offscreen_gl()` checks the system libraries first and raises a
one-line `HitogataError` naming the apt packages, instead of the crash VTK
gives when they are missing. pyvista is imported only when rendering.
"""

from hitogata.render.gl_check import ensure_offscreen_gl
from hitogata.render.images import png_bytes, save_png, side_by_side, titled
from hitogata.render.offscreen import Renderer, render_views
from hitogata.render.scene import Layer, Lines, Points
from hitogata.render.views import VIEWS, View

__all__ = [
    "VIEWS",
    "Layer",
    "Lines",
    "Points",
    "Renderer",
    "View",
    "ensure_offscreen_gl",
    "png_bytes",
    "render_views",
    "save_png",
    "side_by_side",
    "titled",
]
