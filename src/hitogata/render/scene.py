"""What a picture is made of: surfaces, line segments and points, as plain data.

Each item is a frozen dataclass of numpy arrays in the body frame (metres),
checked when made, so a mistake is a one-line `HitogataError` before any
OpenGL is touched. Colours are anything matplotlib understands ("tab:red",
"#d9b59c", (0.8, 0.7, 0.6)).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from matplotlib.colors import to_rgb

from hitogata.errors import HitogataError

Color = str | tuple[float, float, float]


def rgb(color: Color, what: str) -> tuple[float, float, float]:
    """A colour as an RGB triple 0..1, or a one-line error."""
    try:
        return tuple(float(c) for c in to_rgb(color))  # type: ignore[return-value]
    except (ValueError, TypeError):
        raise HitogataError(f"{what} = {color!r}: allowed a matplotlib colour, e.g. 'tab:red' or '#d9b59c'") from None


def finite(name: str, value: object, trailing: tuple[int, ...]) -> np.ndarray:
    """`value` as a finite float array of shape (N, *trailing), N ≥ 1."""
    a = np.asarray(value, dtype=float)
    if a.ndim != 1 + len(trailing) or a.shape[1:] != trailing or len(a) == 0:
        want = ", ".join(["N", *map(str, trailing)])
        raise HitogataError(f"{name}: shape {a.shape} given, expected ({want}) with N ≥ 1")
    if not np.all(np.isfinite(a)):
        raise HitogataError(f"{name}: contains NaN or infinite values")
    return a


def fraction(name: str, value: float) -> float:
    if not 0.0 <= value <= 1.0:
        raise HitogataError(f"{name} = {value!r}: allowed 0..1")
    return float(value)


def positive(name: str, value: float | np.ndarray | None, count: int) -> np.ndarray | None:
    """None, or a radius per element (a scalar is broadcast), all finite and > 0."""
    if value is None:
        return None
    a = np.broadcast_to(np.asarray(value, dtype=float), (count,)) if np.ndim(value) == 0 else np.asarray(value, float)
    if a.shape != (count,) or not np.all(np.isfinite(a)) or np.any(a <= 0):
        raise HitogataError(f"{name}: allowed one positive number or {count} of them")
    return np.array(a)


@dataclass(frozen=True, eq=False)
class Layer:
    """A triangle surface: (V, 3) vertices, (F, 3) faces, one colour or values to colour it by.

    opacity < 1 draws it translucent (nested surfaces show through: depth
    peeling). `scalars` (V,) per vertex or (F,) per face are mapped through
    `colormap` over `clim` (default: their range); `scalar_title` adds a
    colour bar with that title. `backfaces=False` skips faces turned away
    from the camera (faces wound counter-clockwise seen from outside): a
    translucent closed skin then tints what is inside it once, evenly.
    """

    vertices: np.ndarray
    faces: np.ndarray
    color: Color = "#d9b59c"
    opacity: float = 1.0
    scalars: np.ndarray | None = None
    colormap: str = "viridis"
    clim: tuple[float, float] | None = None
    scalar_title: str | None = None
    smooth: bool = True
    backfaces: bool = True

    def __post_init__(self) -> None:
        v = finite("Layer vertices", self.vertices, (3,))
        f = np.asarray(self.faces)
        if f.ndim != 2 or f.shape[1] != 3 or len(f) == 0 or not np.issubdtype(f.dtype, np.integer):
            raise HitogataError(f"Layer faces: shape {f.shape} dtype {f.dtype} given, expected (F ≥ 1, 3) integers")
        if f.min() < 0 or f.max() >= len(v):
            raise HitogataError(f"Layer faces: indices must lie in [0, {len(v)}), got [{f.min()}, {f.max()}]")
        object.__setattr__(self, "vertices", v)
        object.__setattr__(self, "faces", f.astype(np.int64))
        rgb(self.color, "Layer color")
        fraction("Layer opacity", self.opacity)
        if self.scalars is not None:
            s = np.asarray(self.scalars, dtype=float)
            if s.shape not in ((len(v),), (len(f),)) or not np.all(np.isfinite(s)):
                raise HitogataError(
                    f"Layer scalars: shape {s.shape} given, "
                    f"expected finite ({len(v)},) per vertex or ({len(f)},) per face"
                )
            object.__setattr__(self, "scalars", s)
        if self.clim is not None and not (np.all(np.isfinite(self.clim)) and self.clim[0] < self.clim[1]):
            raise HitogataError(f"Layer clim = {self.clim!r}: allowed (low, high) with low < high")


@dataclass(frozen=True, eq=False)
class Lines:
    """(S, 2, 3) line segments: `width` pixels wide, or tubes of `radius` metres (one or (S,)).

    Tubes have round ends (capsules), so a chain of them reads as one limb.
    """

    segments: np.ndarray
    color: Color = "black"
    width: float = 2.0
    radius: float | np.ndarray | None = None
    opacity: float = 1.0

    def __post_init__(self) -> None:
        s = finite("Lines segments", self.segments, (2, 3))
        object.__setattr__(self, "segments", s)
        object.__setattr__(self, "radius", positive("Lines radius", self.radius, len(s)))
        rgb(self.color, "Lines color")
        fraction("Lines opacity", self.opacity)
        if not self.width > 0:
            raise HitogataError(f"Lines width = {self.width!r}: allowed a positive number of pixels")


@dataclass(frozen=True, eq=False)
class Points:
    """(N, 3) points: dots `size` pixels across, or spheres of `radius` metres (one or (N,))."""

    points: np.ndarray
    color: Color = "black"
    size: float = 8.0
    radius: float | np.ndarray | None = None
    opacity: float = 1.0

    def __post_init__(self) -> None:
        p = finite("Points points", self.points, (3,))
        object.__setattr__(self, "points", p)
        object.__setattr__(self, "radius", positive("Points radius", self.radius, len(p)))
        rgb(self.color, "Points color")
        fraction("Points opacity", self.opacity)
        if not self.size > 0:
            raise HitogataError(f"Points size = {self.size!r}: allowed a positive number of pixels")


Item = Layer | Lines | Points
