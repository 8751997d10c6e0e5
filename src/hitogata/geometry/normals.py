"""Vertex normals and vertex areas of a triangle surface."""

from __future__ import annotations

import numpy as np


def vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Unit vertex normals: the sum of adjacent face normals weighted by face area.

    A vertex in no face (or only in degenerate ones) gets +Y so the file stays valid.
    """
    tri = vertices[faces]
    face_normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])  # length = 2 × area
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
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    return np.bincount(faces.ravel(), np.repeat(area / 3.0, 3), minlength=len(vertices))
