"""Capsules and spheres as triangle meshes, built for many at once with numpy.

A capsule is a cylinder of radius r from a to b with hemispherical ends; a
sphere is the two hemispheres alone. Drawing a skeleton's 65 bones as one mesh
(rather than 65 VTK objects) keeps the renderer's work and the code small.
Faces wind counter-clockwise seen from outside.
"""

from __future__ import annotations

import numpy as np

SIDES = 16  # vertices round each ring
RINGS = 4  # rings per hemisphere, the equator included


def _template(sides: int, rings: int, cylinder: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Ring radius ρ, height ζ (in radii), end flag e (0 bottom, 1 top) per ring, and the ring angles φ.

    A sphere (no cylinder) has one equator ring: a doubled one would leave a
    band of zero-area triangles there, whose normals darken the shading.
    """
    bottom = np.pi - np.arange(1, rings + 1) * (np.pi / 2) / rings  # towards the equator
    top = np.pi / 2 - np.arange(0 if cylinder else 1, rings) * (np.pi / 2) / rings
    theta = np.concatenate([bottom, top])
    end = np.concatenate([np.zeros(len(bottom)), np.ones(len(top))])
    phi = np.arange(sides) * 2 * np.pi / sides
    return np.sin(theta), np.cos(theta), end, phi


def _frames(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Right-handed unit frames (u, v, w) with w along each axis ((0, 1, 0) for a zero axis)."""
    length = np.linalg.norm(axis, axis=1, keepdims=True)
    w = np.where(length > 1e-12, axis / np.maximum(length, 1e-300), [0.0, 1.0, 0.0])
    ref = np.where(np.abs(w[:, :1]) < 0.9, [1.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    u = np.cross(w, ref)
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    return u, np.cross(w, u), w


def capsules(
    starts: np.ndarray, ends: np.ndarray, radii: np.ndarray, sides: int = SIDES, rings: int = RINGS
) -> tuple[np.ndarray, np.ndarray]:
    """One mesh (vertices, faces) of capsules from starts (S, 3) to ends (S, 3) with radii (S,)."""
    return _round_mesh(np.asarray(starts, float), np.asarray(ends, float), radii, sides, rings, cylinder=True)


def spheres(
    centres: np.ndarray, radii: np.ndarray, sides: int = SIDES, rings: int = RINGS
) -> tuple[np.ndarray, np.ndarray]:
    """One mesh of spheres at centres (N, 3) with radii (N,)."""
    c = np.asarray(centres, float)
    return _round_mesh(c, c, radii, sides, rings, cylinder=False)


def _round_mesh(
    a: np.ndarray, b: np.ndarray, radii: np.ndarray, sides: int, rings: int, cylinder: bool
) -> tuple[np.ndarray, np.ndarray]:
    r = np.asarray(radii, float)[:, None, None]
    rho, zeta, end, phi = _template(sides, rings, cylinder)
    u, v, w = _frames(b - a)
    length = np.linalg.norm(b - a, axis=1)[:, None, None]
    n_rings = len(rho)
    radial = np.cos(phi)[None, :, None] * u[:, None] + np.sin(phi)[None, :, None] * v[:, None]  # (S, sides, 3)
    along = (r * zeta[None, :, None] + length * end[None, :, None])[..., None] * w[:, None, None]  # (S, R, 1, 3)
    ring_points = a[:, None, None] + (r * rho[None, :, None])[..., None] * radial[:, None] + along
    poles = np.stack([a - r[:, 0] * w, b + r[:, 0] * w], axis=1)  # (S, 2, 3)
    per = n_rings * sides + 2
    vertices = np.concatenate([ring_points.reshape(len(a), -1, 3), poles], axis=1).reshape(-1, 3)

    ring = np.arange(n_rings * sides).reshape(n_rings, sides)
    nxt = np.roll(ring, -1, axis=1)
    bottom, top = n_rings * sides, n_rings * sides + 1
    bands = np.concatenate(
        [
            np.stack([ring[:-1], nxt[:-1], nxt[1:]], axis=-1).reshape(-1, 3),
            np.stack([ring[:-1], nxt[1:], ring[1:]], axis=-1).reshape(-1, 3),
            np.stack([np.full(sides, bottom), nxt[0], ring[0]], axis=-1),
            np.stack([ring[-1], nxt[-1], np.full(sides, top)], axis=-1),
        ]
    )
    faces = (bands[None] + per * np.arange(len(a))[:, None, None]).reshape(-1, 3)
    return vertices, faces

