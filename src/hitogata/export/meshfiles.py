"""Plain triangle-mesh files (OBJ, PLY, unskinned GLB) through trimesh.

For a skinned, posable GLB use :func:`hitogata.export.gltf.write_glb`.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from hitogata.errors import HitogataError
from hitogata.export.atomic import write_bytes_atomically

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
    import trimesh  # only when a mesh file is written

    mesh = trimesh.Trimesh(
        vertices=np.asarray(vertices, dtype=np.float64),
        faces=np.asarray(faces, dtype=np.int64),
        process=False,
    )
    data = mesh.export(file_type=suffix[1:])
    if isinstance(data, str):
        data = data.encode("utf-8")
    return write_bytes_atomically(path, data)
