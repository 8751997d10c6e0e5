"""Plain triangle-mesh files: PLY written with numpy (`export.ply`), OBJ and unskinned GLB through trimesh.

For a skinned, posable GLB use :func:`hitogata.export.gltf.write_glb`.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from hitogata.errors import HitogataError
from hitogata.export.atomic import write_bytes_atomically
from hitogata.export.ply import ply_bytes

MESH_SUFFIXES = (".glb", ".obj", ".ply")


def write_mesh(path: str | os.PathLike, vertices: np.ndarray, faces: np.ndarray) -> Path:
    """Write a triangle mesh to ``path``; the format follows the suffix (.glb, .obj, .ply).

    Vertex order is kept (no merging or cleaning), so indices match the model's.
    PLY is binary little-endian. The write is atomic.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in MESH_SUFFIXES:
        raise HitogataError(
            f"{path}: unknown mesh file suffix {path.suffix!r}; allowed: {', '.join(MESH_SUFFIXES)}"
        )
    vertices, faces = np.asarray(vertices, dtype=np.float64), np.asarray(faces)
    if vertices.ndim != 2 or vertices.shape[1] != 3 or not np.isfinite(vertices).all():
        bad = "" if vertices.ndim != 2 or vertices.shape[1] != 3 else \
            f", vertex {int(np.flatnonzero(~np.isfinite(vertices).all(axis=1))[0])} not finite"
        raise HitogataError(f"{path}: vertices of shape {vertices.shape}{bad}; allowed (V, 3) finite numbers")
    if faces.ndim != 2 or faces.shape[1] != 3 or faces.dtype.kind not in "iu" or (
            faces.size and not (0 <= faces.min() and faces.max() < len(vertices))):
        raise HitogataError(f"{path}: faces of shape {faces.shape}; allowed (F, 3) vertex indices 0..{len(vertices) - 1}")
    if suffix == ".ply":
        return write_bytes_atomically(path, ply_bytes(vertices, faces))
    import trimesh  # only when an OBJ or GLB is written

    mesh = trimesh.Trimesh(vertices=vertices, faces=faces.astype(np.int64), process=False)
    data = mesh.export(file_type=suffix[1:])
    if isinstance(data, str):
        data = data.encode("utf-8")
    return write_bytes_atomically(path, data)
