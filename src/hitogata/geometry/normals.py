"""Normals and areas of a triangle surface: per triangle, per face, per vertex. The one place for them."""

from __future__ import annotations

import numpy as np


def triangle_normals(tri: np.ndarray) -> np.ndarray:
    """(F, 3) normals of triangles (F, 3, 3) by the right-hand rule, not normalised: each is twice the
    triangle's area long (outward on an outward-oriented surface)."""
    return np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])


def triangle_areas(tri: np.ndarray) -> np.ndarray:
    """(F,) areas of triangles (F, 3, 3)."""
    return 0.5 * np.linalg.norm(triangle_normals(tri), axis=1)


def face_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(F, 3) unit face normals (outward on an outward-oriented surface); a degenerate face's is zero."""
    n = triangle_normals(vertices[faces])
    return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-20)


def vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Unit vertex normals: the sum of adjacent face normals weighted by face area.

    A vertex in no face (or only in degenerate ones) gets +Y so the file stays valid.
    """
    tri = vertices[faces]
    face_normals = triangle_normals(tri)  # length = 2 × area
    summed = np.stack(
        [np.bincount(faces.ravel(), np.repeat(face_normals[:, c], 3), minlength=len(vertices)) for c in range(3)],
        axis=1,
    )
    length = np.linalg.norm(summed, axis=1)
    unit = np.tile([0.0, 1.0, 0.0], (len(vertices), 1))
    ok = length > 0
    unit[ok] = summed[ok] / length[ok, None]
    return unit


def vertex_areas(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Each vertex's share of the surface's area (m²): a third of each triangle it is a corner of."""
    tri = vertices[faces]
    area = triangle_areas(tri)
    return np.bincount(faces.ravel(), np.repeat(area / 3.0, 3), minlength=len(vertices))
