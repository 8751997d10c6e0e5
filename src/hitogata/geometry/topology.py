"""Edge structure of a fixed triangle mesh, computed once per `faces` array.

Planar sections need the mesh's unique edges and, for each face, the ids of
its three edges. The body's topology never changes, so this is cached by the
faces' content and reused for every posture and every frame of a sequence.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import numpy as np

_CACHE: dict[bytes, "Topology"] = {}
_CACHE_SIZE = 8


@dataclass(frozen=True, eq=False)
class Topology:
    """Unique undirected edges (E, 2) and each face's edge ids (F, 3): (v0v1, v1v2, v2v0)."""

    faces: np.ndarray
    edges: np.ndarray
    face_edges: np.ndarray


def topology(faces: np.ndarray) -> Topology:
    """The edge structure of `faces`, cached by their content."""
    faces = np.ascontiguousarray(faces, dtype=np.int64)
    key = hashlib.blake2b(faces.tobytes(), digest_size=16).digest() + repr(faces.shape).encode()
    found = _CACHE.get(key)
    if found is None:
        found = _build(faces)
        if len(_CACHE) >= _CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = found
    return found


def _build(faces: np.ndarray) -> Topology:
    n = int(faces.max()) + 1 if faces.size else 1
    directed = np.stack([faces, np.roll(faces, -1, axis=1)], axis=2).reshape(-1, 2)
    keys = np.sort(directed, axis=1) @ np.array([n, 1], dtype=np.int64)
    unique, inverse = np.unique(keys, return_inverse=True)
    return Topology(
        faces=faces,
        edges=np.stack([unique // n, unique % n], axis=1),
        face_edges=inverse.reshape(-1, 3),
    )
