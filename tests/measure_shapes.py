"""Closed test surfaces with known girths and geodesics: prisms over a star-shaped outline."""

from __future__ import annotations

import numpy as np


def prism(outline: np.ndarray, height: float, rings: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """Closed, outward-oriented prism: the 2-D outline (N, 2) in x–z, from y = 0 to y = height.

    `rings` vertex rings along y; side quads split into triangles; caps are fans
    round a centre point (so the outline must be star-shaped about the origin).
    """
    n = len(outline)
    ys = np.linspace(0.0, height, rings)
    side = np.array([[x, y, z] for y in ys for x, z in outline])
    centres = np.array([[0.0, 0.0, 0.0], [0.0, height, 0.0]])
    vertices = np.vstack([side, centres])
    bottom, top = len(side), len(side) + 1
    faces = []
    for r in range(rings - 1):
        for k in range(n):
            a, b = r * n + k, r * n + (k + 1) % n
            c, d = a + n, b + n
            faces += [[a, c, b], [b, c, d]]
    for k in range(n):
        faces.append([k, (k + 1) % n, bottom])
        faces.append([(rings - 1) * n + (k + 1) % n, (rings - 1) * n + k, top])
    return vertices, np.array(faces, dtype=np.int64)[:, ::-1].copy()


def circle(radius: float, n: int, centre: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
    """n points on a circle in the x–z plane."""
    t = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    return np.stack([centre[0] + radius * np.cos(t), centre[1] - radius * np.sin(t)], axis=1)


def ellipse(a: float, b: float, n: int) -> np.ndarray:
    """n points on the ellipse x = a cos t, z = −b sin t."""
    t = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    return np.stack([a * np.cos(t), -b * np.sin(t)], axis=1)


def two_circles(radius: float, offset: float, n: int) -> np.ndarray:
    """Outline of the union of two circles of `radius` centred at x = ±offset (offset < radius)."""
    t = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    c, s = np.cos(t), np.sin(t)
    reach = np.maximum(
        offset * c + np.sqrt(radius**2 - (offset * s) ** 2),
        -offset * c + np.sqrt(radius**2 - (offset * s) ** 2),
    )
    return np.stack([reach * c, -reach * s], axis=1)


def ramanujan_ii(a: float, b: float) -> float:
    """Perimeter of an ellipse with semi-axes a, b (Ramanujan's second approximation)."""
    h = ((a - b) / (a + b)) ** 2
    return float(np.pi * (a + b) * (1.0 + 3.0 * h / (10.0 + np.sqrt(4.0 - 3.0 * h))))
