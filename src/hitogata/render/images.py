"""Images as arrays: put views side by side and write PNG files atomically."""

from __future__ import annotations

import io
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.image import imsave

from hitogata.errors import HitogataError
from hitogata.export.atomic import write_bytes_atomically
from hitogata.render.scene import Color, rgb


def _image(image: np.ndarray, what: str) -> np.ndarray:
    a = np.asarray(image)
    if a.ndim != 3 or a.shape[2] not in (3, 4) or a.dtype != np.uint8 or 0 in a.shape:
        raise HitogataError(f"{what}: shape {a.shape} dtype {a.dtype} given, expected (height, width, 3 or 4) uint8")
    return a


def side_by_side(images: Sequence[np.ndarray], gap: int = 0, background: Color = "white") -> np.ndarray:
    """RGB images left to right, top-aligned, `gap` pixels apart, padded with the background."""
    parts = [_image(im, "side_by_side image")[..., :3] for im in images]
    if not parts:
        raise HitogataError("side_by_side: no images given")
    fill = np.round(np.array(rgb(background, "background")) * 255).astype(np.uint8)
    height = max(p.shape[0] for p in parts)
    width = sum(p.shape[1] for p in parts) + gap * (len(parts) - 1)
    out = np.empty((height, width, 3), dtype=np.uint8)
    out[:] = fill
    x = 0
    for p in parts:
        out[: p.shape[0], x : x + p.shape[1]] = p
        x += p.shape[1] + gap
    return out


TITLE_PIXELS = 22  # height of a title band
TITLE_POINTS = 13


def titled(image: np.ndarray, title: str, background: Color = "white", color: Color = "#333333") -> np.ndarray:
    """The image with a band of TITLE_PIXELS on top holding `title`, centred (cut with "…" if too long)."""
    from PIL import Image, ImageDraw, ImageFont

    a = _image(image, "titled image")[..., :3]
    fill = tuple(round(c * 255) for c in rgb(background, "background"))
    ink = tuple(round(c * 255) for c in rgb(color, "title color"))
    band = Image.new("RGB", (a.shape[1], TITLE_PIXELS), fill)
    draw = ImageDraw.Draw(band)
    font = ImageFont.load_default(size=TITLE_POINTS)
    text = title
    while len(text) > 1 and draw.textlength(text, font=font) > a.shape[1] - 8:
        text = text[:-2] + "…"
    draw.text((a.shape[1] / 2, TITLE_PIXELS / 2), text, font=font, fill=ink, anchor="mm")
    return np.concatenate([np.asarray(band), a], axis=0)


def png_bytes(image: np.ndarray) -> bytes:
    """An (H, W, 3|4) uint8 image as PNG bytes."""
    buffer = io.BytesIO()
    imsave(buffer, _image(image, "png image"), format="png")
    return buffer.getvalue()


def save_png(path: str | os.PathLike, image: np.ndarray) -> Path:
    """Write an (H, W, 3|4) uint8 image as PNG, atomically; return the path."""
    path = Path(path)
    if path.suffix.lower() != ".png":
        raise HitogataError(f"{path}: save_png writes .png files only, got suffix {path.suffix!r}")
    return write_bytes_atomically(path, png_bytes(image))
