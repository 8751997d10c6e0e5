"""Binary PLY files of a triangle mesh, written with numpy alone.

The layout is the common one (as trimesh and meshio write and read it): little-endian,
vertices as three float32 `x y z`, faces as a uchar count (3) and three int32 vertex
indices. Written here rather than through trimesh, whose import alone costs a held pose
on the command line a quarter of a second.
"""

from __future__ import annotations

import numpy as np

VERTEX = np.dtype([("xyz", "<f4", (3,))])
FACE = np.dtype([("count", "u1"), ("index", "<i4", (3,))])


def ply_bytes(vertices: np.ndarray, faces: np.ndarray) -> bytes:
    """The PLY file of `vertices` (V, 3) and triangles `faces` (F, 3) (vertex order kept; checked by the caller)."""
    header = "\n".join([
        "ply",
        "format binary_little_endian 1.0",
        "comment hitogata",
        f"element vertex {len(vertices)}",
        "property float x",
        "property float y",
        "property float z",
        f"element face {len(faces)}",
        "property list uchar int vertex_indices",
        "end_header",
        "",
    ])
    packed_vertices = np.empty(len(vertices), dtype=VERTEX)
    packed_vertices["xyz"] = vertices
    packed_faces = np.empty(len(faces), dtype=FACE)
    packed_faces["count"] = 3
    packed_faces["index"] = faces
    return header.encode("ascii") + packed_vertices.tobytes() + packed_faces.tobytes()
