"""Read back the skinned mesh of a GLB (glTF 2.0 binary): the arrays `gltf.write_glb` takes.

The container is read directly (a 12-byte header, then a JSON chunk and a
binary chunk, glTF 2.0 §4.4), the document as plain JSON: `hitogata measure`
of a body file needs its skin and extras, not the writer's library (pygltflib
builds an object per JSON entry, which took longer than the rest of the read).
"""

from __future__ import annotations

import json
import os
import struct
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from scipy import sparse

from hitogata.errors import HitogataError, excerpt

MAGIC, JSON_CHUNK, BIN_CHUNK = b"glTF", 0x4E4F534A, 0x004E4942
COMPONENT_DTYPES: dict[int, np.dtype] = {  # glTF componentType → dtype
    5120: np.dtype("i1"),
    5121: np.dtype("u1"),
    5122: np.dtype("<i2"),
    5123: np.dtype("<u2"),
    5125: np.dtype("<u4"),
    5126: np.dtype("<f4"),
}
TYPE_WIDTHS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}


@dataclass(frozen=True)
class GlbSkin:
    """The first skinned mesh of a GLB file, in the arrays write_glb takes."""

    vertices: np.ndarray  # (V, 3) float64
    faces: np.ndarray  # (F, 3) int64
    normals: np.ndarray | None  # (V, 3) float64
    joint_names: tuple[str, ...]
    joint_parents: np.ndarray  # (J,) int64, -1 for roots
    joint_positions: np.ndarray  # (J, 3) float64, bind-pose world positions
    skin_weights: sparse.csr_matrix  # (V, J)
    extras: dict = field(default_factory=dict)


def read_glb_skin(path: str | os.PathLike) -> GlbSkin:
    """Read back the first skinned mesh node of a GLB (first primitive) for checks and round trips.

    A file that is not a whole, well-formed GLB (empty, truncated, random bytes)
    is a one-line `HitogataError`, whatever part of the reading it breaks.
    """
    path = Path(path)
    try:
        return _read_glb_skin(path)
    except HitogataError:
        raise
    except RecursionError:
        raise HitogataError(f"{path}: not a readable GLB file (its JSON is nested too deep); allowed a .glb written "
                            "by hitogata") from None
    except (OSError, ValueError, struct.error, KeyError, IndexError, TypeError, AttributeError,
            np.linalg.LinAlgError) as err:
        reason = str(err).splitlines()[0] if str(err) else type(err).__name__
        raise HitogataError(f"{path}: not a readable GLB file ({excerpt(reason, 100)}); allowed a .glb written by "
                            "hitogata") from None


def read_glb(path: Path) -> tuple[dict[str, Any], bytes | None]:
    """The JSON document and the binary chunk (None if there is none) of a GLB file."""
    data = path.read_bytes()
    magic, _, length = struct.unpack_from("<4sII", data, 0)
    if magic != MAGIC:
        raise ValueError(f"starts with {magic!r}, not {MAGIC!r}")
    if length > len(data):
        raise ValueError(f"{len(data)} bytes of the {length} its header gives")
    document, blob, at = None, None, 12
    while at < length:
        size, kind = struct.unpack_from("<II", data, at)
        if at + 8 + size > length:
            raise ValueError(f"a chunk of {size} bytes at byte {at} runs past the file's end")
        chunk = data[at + 8: at + 8 + size]
        if kind == JSON_CHUNK and document is None:
            document = json.loads(chunk)
        elif kind == BIN_CHUNK and blob is None:
            blob = chunk
        at += 8 + size
    if not isinstance(document, dict):
        raise ValueError("no JSON document")
    return document, blob


def _read_glb_skin(path: Path) -> GlbSkin:
    if path.stat().st_size < 20:
        raise HitogataError(f"{path}: {path.stat().st_size} bytes, not a GLB file; allowed a .glb written by hitogata")
    document, blob = read_glb(path)
    nodes = document.get("nodes", [])
    node = next((n for n in nodes if n.get("mesh") is not None and n.get("skin") is not None), None)
    if node is None or blob is None:
        raise HitogataError(f"{path}: no skinned mesh with embedded binary data found")
    skin = document["skins"][node["skin"]]
    primitive = document["meshes"][node["mesh"]]["primitives"][0]
    attributes = primitive["attributes"]

    def required(index: int | None, what: str) -> np.ndarray:
        if index is None:
            raise HitogataError(f"{path}: the skinned mesh has no {what}; allowed a .glb written by hitogata")
        return _read_accessor(document, blob, index)

    joint_nodes = skin["joints"]
    joint_of_node = {n: j for j, n in enumerate(joint_nodes)}
    parent_node = {c: p for p, parent in enumerate(nodes) for c in parent.get("children") or []}
    parents = np.array([joint_of_node.get(parent_node.get(n, -1), -1) for n in joint_nodes], dtype=np.int64)
    if skin.get("inverseBindMatrices") is None:
        positions = np.zeros((len(joint_nodes), 3))
    else:
        ibm = _read_accessor(document, blob, skin["inverseBindMatrices"]).reshape(-1, 4, 4).transpose(0, 2, 1)
        positions = np.linalg.inv(ibm)[:, :3, 3]

    vertices = required(attributes.get("POSITION"), "POSITION").astype(np.float64)
    n_vertices = len(vertices)
    joints = required(attributes.get("JOINTS_0"), "JOINTS_0")
    weights = required(attributes.get("WEIGHTS_0"), "WEIGHTS_0").astype(np.float64)
    rows = np.repeat(np.arange(n_vertices), joints.shape[1])
    skin_weights = sparse.csr_matrix(
        (weights.ravel(), (rows, joints.ravel())), shape=(n_vertices, len(joint_nodes))
    )
    skin_weights.eliminate_zeros()
    normals = None if attributes.get("NORMAL") is None else _read_accessor(document, blob, attributes["NORMAL"])
    return GlbSkin(
        vertices=vertices,
        faces=required(primitive.get("indices"), "indices").astype(np.int64).reshape(-1, 3),
        normals=None if normals is None else normals.astype(np.float64),
        joint_names=tuple((nodes[n].get("extras") or {}).get("name", nodes[n].get("name")) for n in joint_nodes),
        joint_parents=parents,
        joint_positions=positions,
        skin_weights=skin_weights,
        extras={k: v for k, v in (node.get("extras") or {}).items() if k != "name"},  # "name": the node's own
    )


def _whole(value: Any, what: str) -> int:
    """A non-negative whole number from the document (a count, an index, a byte offset)."""
    if not isinstance(value, int) or isinstance(value, bool) or value < 0:
        raise ValueError(f"{what} {excerpt(value)}: allowed a whole number >= 0")
    return value


def _read_accessor(document: dict[str, Any], blob: bytes, index: int) -> np.ndarray:
    """An accessor's data as an array (count, width), honouring byte offsets and strides."""
    accessor = document["accessors"][_whole(index, "accessor index")]
    view = document["bufferViews"][_whole(accessor["bufferView"], f"accessor {index} bufferView")]
    dtype = COMPONENT_DTYPES[accessor["componentType"]]
    width = TYPE_WIDTHS[accessor["type"]]
    count = _whole(accessor["count"], f"accessor {index} count")
    stride = _whole(view.get("byteStride") or width * dtype.itemsize, f"bufferView {accessor['bufferView']} byteStride")
    offset = _whole(view.get("byteOffset", 0), "bufferView byteOffset") + _whole(accessor.get("byteOffset", 0),
                                                                               f"accessor {index} byteOffset")
    end = offset + (count - 1) * stride + width * dtype.itemsize if count else offset
    if stride < width * dtype.itemsize or end > len(blob):  # bounded by the file before anything is allocated
        raise ValueError(f"accessor {index}: {count} items of {width * dtype.itemsize} bytes every {stride} from "
                         f"byte {offset} need {end} bytes; the binary chunk has {len(blob)}")
    data = np.ndarray(shape=(count, width), dtype=dtype, buffer=blob, offset=offset, strides=(stride, dtype.itemsize))
    return data.copy() if width > 1 else data[:, 0].copy()
