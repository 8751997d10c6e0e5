"""Named camera views in the body frame and the framing shared by all views of a picture.

The body frame: +Y up, +Z the body's front, +X the body's left. A view is the
direction the camera looks along and the screen's up: "front" looks along −Z
(the body's left on the picture's right), "side" is the body's left side
(looking along −X, the front on the picture's left), "back", "right" and
"top" (looking down, the front at the bottom of the picture). Projection is
orthographic, as in a technical drawing, and every view of one picture gets
the same scale with the scene's centre at the same height, so front and side
views line up.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.errors import HitogataError


@dataclass(frozen=True)
class View:
    """A camera: `direction` it looks along, `up` on the screen (both body frame), a `name` for labels."""

    name: str
    direction: tuple[float, float, float]
    up: tuple[float, float, float]

    def axes(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Unit (screen right, screen up, viewing direction)."""
        d = np.asarray(self.direction, float)
        d /= np.linalg.norm(d)
        up = np.asarray(self.up, float)
        up = up - (up @ d) * d
        if np.linalg.norm(up) < 1e-6:
            raise HitogataError(f"view {self.name!r}: up {self.up} is parallel to the direction {self.direction}")
        up /= np.linalg.norm(up)
        return np.cross(d, up), up, d


VIEWS = {
    "front": View("front", (0.0, 0.0, -1.0), (0.0, 1.0, 0.0)),
    "side": View("left side", (-1.0, 0.0, 0.0), (0.0, 1.0, 0.0)),
    "back": View("back", (0.0, 0.0, 1.0), (0.0, 1.0, 0.0)),
    "right": View("right side", (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)),
    "top": View("top", (0.0, -1.0, 0.0), (0.0, 0.0, -1.0)),
}


def view(spec: str | View) -> View:
    """A View from its name (see VIEWS) or as given."""
    if isinstance(spec, View):
        return spec
    if spec not in VIEWS:
        raise HitogataError(f"view {spec!r}: allowed {', '.join(VIEWS)} or a View(name, direction, up)")
    return VIEWS[spec]


@dataclass(frozen=True)
class Framing:
    """Where each view of a picture points, at one scale for all.

    `half_height`: half the screen's height in metres; `focal`: per view, the
    point at the screen's centre; `half_widths`: per view, half the width the
    content needs (metres, margin included); `distance`: camera to focal point.
    """

    half_height: float
    focal: tuple[np.ndarray, ...]
    half_widths: tuple[float, ...]
    distance: float


def frame_views(
    points: np.ndarray,
    views: list[View],
    aspect: float | None,
    margin: float,
    top: float = 0.0,
    bottom: float = 0.0,
) -> Framing:
    """The framing that fits `points` (K, 3) into every view with `margin` (fraction) to spare.

    `aspect` is the image's width / height; None: the height alone sets the
    scale (each image is then made as wide as its view needs). `top` and
    `bottom` are fractions of the image's height kept free (for a label, a
    colour bar); the content is centred in the band between them.
    """
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre = 0.5 * (lo + hi)
    rel = points - centre
    axes = [v.axes() for v in views]
    heights = [np.abs(rel @ up).max() * (1.0 + margin) for _, up, _ in axes]
    widths = tuple(float(np.abs(rel @ right).max()) * (1.0 + margin) for right, _, _ in axes)
    band = 1.0 - top - bottom
    half = max(max(heights) / band, max(widths) / aspect if aspect else 0.0, 1e-6)
    focal = tuple(centre - up * half * (bottom - top) for _, up, _ in axes)
    radius = float(np.linalg.norm(hi - lo)) / 2
    return Framing(float(half), focal, widths, 4.0 * max(radius, 1e-6))
