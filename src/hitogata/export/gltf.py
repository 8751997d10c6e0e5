"""Skinned glTF 2.0 binary (GLB) export with pygltflib (reading back: `glb_read`).

The body's frame (+Y up, +Z forward, metres) is glTF's own, so coordinates are
written unchanged. The rest pose is the bind pose: each joint is a node with a
translation from its parent and no rotation, all joints hang under one
``armature`` node (the validator wants a common root), and the skinned mesh
node sits beside it at the scene root, as the glTF spec asks.

Building is split from writing: :class:`GlbBuilder` holds a document and its
binary chunk, :func:`add_skinned_mesh` puts a body into it and returns the
node indices, and :meth:`GlbBuilder.to_bytes` serialises. A later writer can
add more in between (e.g. animation samplers for several frames, targeting
those joint nodes) without touching the body code.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np
import pygltflib as gl
from scipy import sparse

from hitogata.errors import HitogataError
from hitogata.export.atomic import write_bytes_atomically
from hitogata.geometry.normals import vertex_normals

MAX_INFLUENCES = 4  # joints per vertex in JOINTS_0 / WEIGHTS_0
SKIN_RGBA = (0.89, 0.72, 0.60, 1.0)  # the body's material: a plain skin tone, matte
_UNSAFE = re.compile(r"[^A-Za-z0-9_-]")


def safe_name(name: str) -> str:
    """A node name three.js's loader keeps as is (it rewrites '.', ':', '/', '[', ']' and spaces)."""
    return _UNSAFE.sub("_", name)


def named_node(name: str, **fields: Any) -> gl.Node:
    """A node under its safe name; the name as given (e.g. MakeHuman's 'upperarm01.L') kept in extras."""
    safe = safe_name(name)
    return gl.Node(name=safe, extras={"name": name} if safe != name else {}, **fields)


def add_material(builder: GlbBuilder, name: str, rgba: Sequence[float], roughness: float = 0.8) -> int:
    """A matte PBR material (translucent when alpha < 1, both sides then); return its index."""
    translucent = rgba[3] < 1.0
    builder.gltf.materials.append(gl.Material(
        name=name, alphaMode="BLEND" if translucent else "OPAQUE", doubleSided=translucent,
        pbrMetallicRoughness=gl.PbrMetallicRoughness(baseColorFactor=[float(c) for c in rgba], metallicFactor=0.0,
                                                     roughnessFactor=roughness)))
    return len(builder.gltf.materials) - 1

_COMPONENT_TYPES = {
    np.dtype("<f4"): gl.FLOAT,
    np.dtype("<u2"): gl.UNSIGNED_SHORT,
    np.dtype("<u4"): gl.UNSIGNED_INT,
}


# --------------------------------------------------------------------------- building


class GlbBuilder:
    """A glTF document with a single binary buffer, grown accessor by accessor."""

    def __init__(self, generator: str = "hitogata") -> None:
        self.gltf = gl.GLTF2(asset=gl.Asset(generator=generator, version="2.0"), scene=0, scenes=[gl.Scene()])
        self._chunks: list[bytes] = []
        self._length = 0

    def add_accessor(
        self, array: np.ndarray, accessor_type: str, *, target: int | None = None, with_bounds: bool = False
    ) -> int:
        """Append ``array`` (float32, uint16 or uint32) as a buffer view + accessor; return its index.

        ``with_bounds`` records per-component min/max (required for POSITION).
        """
        array = np.ascontiguousarray(array, dtype=array.dtype.newbyteorder("<"))
        if array.dtype not in _COMPONENT_TYPES:
            raise TypeError(f"add_accessor: dtype {array.dtype} given, expected float32, uint16 or uint32")
        data = array.tobytes()
        self.gltf.bufferViews.append(
            gl.BufferView(buffer=0, byteOffset=self._length, byteLength=len(data), target=target)
        )
        padded = data + b"\0" * (-len(data) % 4)
        self._chunks.append(padded)
        self._length += len(padded)
        columns = array.reshape(len(array), -1)
        accessor = gl.Accessor(
            bufferView=len(self.gltf.bufferViews) - 1,
            componentType=_COMPONENT_TYPES[array.dtype],
            count=len(array),
            type=accessor_type,
        )
        if with_bounds:
            accessor.min = [float(x) for x in columns.min(axis=0)]
            accessor.max = [float(x) for x in columns.max(axis=0)]
        self.gltf.accessors.append(accessor)
        return len(self.gltf.accessors) - 1

    def add_node(self, node: gl.Node, *, root: bool = False) -> int:
        """Append a node (to the scene's roots if ``root``); return its index."""
        self.gltf.nodes.append(node)
        index = len(self.gltf.nodes) - 1
        if root:
            self.gltf.scenes[0].nodes.append(index)
        return index

    def to_bytes(self) -> bytes:
        """The GLB file contents; the same document always gives the same bytes."""
        blob = b"".join(self._chunks)
        self.gltf.buffers = [gl.Buffer(byteLength=len(blob))]
        self.gltf.set_binary_blob(blob)
        return b"".join(self.gltf.save_to_bytes())


@dataclass(frozen=True)
class SkinnedMeshNodes:
    """Node indices of a skinned mesh in a :class:`GlbBuilder` document."""

    joints: tuple[int, ...]  # node of joint j, in the caller's joint order
    armature: int
    mesh: int


def add_skinned_mesh(
    builder: GlbBuilder,
    vertices: np.ndarray,
    faces: np.ndarray,
    *,
    joint_names: Sequence[str],
    joint_parents: np.ndarray,
    joint_positions: np.ndarray,
    skin_weights: np.ndarray | sparse.spmatrix | sparse.sparray,
    normals: np.ndarray | None = None,
    name: str = "hitogata body",
    extras: Mapping[str, Any] | None = None,
) -> SkinnedMeshNodes:
    """Add a mesh bound to a joint hierarchy in its rest (bind) pose; see :func:`write_glb`."""
    vertices = _finite_array("vertices", vertices, (None, 3))
    n_vertices = len(vertices)
    faces = _face_array(faces, n_vertices)
    names = [str(n) for n in joint_names]
    if not names or len(set(names)) != len(names):
        raise HitogataError(f"joint_names: need at least one name and no duplicates, got {len(names)} names")
    parents = _parent_array(joint_parents, len(names))
    positions = _finite_array("joint_positions", joint_positions, (len(names), 3))
    joints, weights = limit_influences(skin_weights, (n_vertices, len(names)))
    normals = vertex_normals(vertices, faces) if normals is None else _unit_normals(normals, n_vertices)

    first = len(builder.gltf.nodes)  # joint j becomes node first + j
    for j, joint in enumerate(names):
        offset = positions[j] - positions[parents[j]] if parents[j] >= 0 else positions[j]
        children = [first + int(c) for c in np.flatnonzero(parents == j)]
        builder.add_node(named_node(joint, translation=[float(x) for x in offset], children=children))
    joint_nodes = list(range(first, first + len(names)))
    roots = [first + int(j) for j in np.flatnonzero(parents < 0)]
    armature = builder.add_node(gl.Node(name="armature", children=roots), root=True)

    inverse_bind = np.tile(np.eye(4), (len(names), 1, 1))
    inverse_bind[:, :3, 3] = -positions
    ibm = builder.add_accessor(inverse_bind.transpose(0, 2, 1).astype(np.float32), gl.MAT4)  # column-major
    builder.gltf.skins.append(
        gl.Skin(name=f"{name} skin", inverseBindMatrices=ibm, joints=joint_nodes, skeleton=armature)
    )

    attributes = gl.Attributes(
        POSITION=builder.add_accessor(vertices.astype(np.float32), gl.VEC3, target=gl.ARRAY_BUFFER, with_bounds=True),
        NORMAL=builder.add_accessor(normals.astype(np.float32), gl.VEC3, target=gl.ARRAY_BUFFER),
        JOINTS_0=builder.add_accessor(joints, gl.VEC4, target=gl.ARRAY_BUFFER),
        WEIGHTS_0=builder.add_accessor(weights, gl.VEC4, target=gl.ARRAY_BUFFER),
    )
    indices = builder.add_accessor(faces.astype(np.uint32).reshape(-1), gl.SCALAR, target=gl.ELEMENT_ARRAY_BUFFER)
    material = add_material(builder, "skin", SKIN_RGBA)
    builder.gltf.meshes.append(gl.Mesh(name=safe_name(name), primitives=[
        gl.Primitive(attributes=attributes, indices=indices, mode=gl.TRIANGLES, material=material)]))
    mesh_node = named_node(name, mesh=len(builder.gltf.meshes) - 1, skin=len(builder.gltf.skins) - 1)
    if extras:
        mesh_node.extras = {**mesh_node.extras, **dict(extras)}
    mesh = builder.add_node(mesh_node, root=True)
    return SkinnedMeshNodes(joints=tuple(joint_nodes), armature=armature, mesh=mesh)


def add_mesh(builder: GlbBuilder, vertices: np.ndarray, faces: np.ndarray, name: str, rgba: Sequence[float],
             double_sided: bool = False) -> int:
    """Add a plain (unskinned) triangle mesh as a root node with its own material; return the node.
    double_sided: drawn from both sides (an open surface such as a garment)."""
    vertices = _finite_array("vertices", vertices, (None, 3))
    faces = _face_array(faces, len(vertices))
    attributes = gl.Attributes(
        POSITION=builder.add_accessor(vertices.astype(np.float32), gl.VEC3, target=gl.ARRAY_BUFFER, with_bounds=True),
        NORMAL=builder.add_accessor(vertex_normals(vertices, faces).astype(np.float32), gl.VEC3,
                                    target=gl.ARRAY_BUFFER),
    )
    indices = builder.add_accessor(faces.astype(np.uint32).reshape(-1), gl.SCALAR, target=gl.ELEMENT_ARRAY_BUFFER)
    material = add_material(builder, name, rgba)
    builder.gltf.materials[material].doubleSided = double_sided or builder.gltf.materials[material].doubleSided
    builder.gltf.meshes.append(gl.Mesh(name=safe_name(name), primitives=[
        gl.Primitive(attributes=attributes, indices=indices, mode=gl.TRIANGLES, material=material)]))
    return builder.add_node(named_node(name, mesh=len(builder.gltf.meshes) - 1), root=True)


def write_glb(
    path: str | os.PathLike,
    vertices: np.ndarray,
    faces: np.ndarray,
    *,
    joint_names: Sequence[str],
    joint_parents: np.ndarray,
    joint_positions: np.ndarray,
    skin_weights: np.ndarray | sparse.spmatrix | sparse.sparray,
    normals: np.ndarray | None = None,
    name: str = "hitogata body",
    extras: Mapping[str, Any] | None = None,
) -> Path:
    """Write a skinned body as GLB, atomically; return the path.

    vertices (V, 3) metres, faces (F, 3); joints: names (J), parents (J,) with
    -1 for roots, rest-pose world positions (J, 3); skin_weights (V, J) dense
    or scipy.sparse, non-negative: the 4 largest per vertex are kept and
    renormalised. Normals are area-weighted vertex normals unless given.
    ``extras`` (JSON-able, e.g. stature) go on the mesh node.
    """
    path = Path(path)
    if path.suffix.lower() != ".glb":
        raise HitogataError(f"{path}: write_glb writes .glb files only, got suffix {path.suffix!r}")
    builder = GlbBuilder()
    add_skinned_mesh(
        builder,
        vertices,
        faces,
        joint_names=joint_names,
        joint_parents=joint_parents,
        joint_positions=joint_positions,
        skin_weights=skin_weights,
        normals=normals,
        name=name,
        extras=extras,
    )
    return write_bytes_atomically(path, builder.to_bytes())


# --------------------------------------------------------------------------- input preparation


def limit_influences(
    skin_weights: np.ndarray | sparse.spmatrix | sparse.sparray,
    shape: tuple[int, int],
    max_influences: int = MAX_INFLUENCES,
) -> tuple[np.ndarray, np.ndarray]:
    """Keep each vertex's ``max_influences`` largest weights, renormalised to sum to 1.

    Returns joints (V, k) uint16 and weights (V, k) float32, largest first;
    empty slots have weight 0 and joint 0 (so the glTF validator sees no
    weightless joint references). Ties go to the lower joint index.
    """
    if sparse.issparse(skin_weights):
        w = sparse.csr_matrix(skin_weights, dtype=np.float64)
    else:
        w = sparse.csr_matrix(_finite_array("skin_weights", skin_weights, shape))
    if w.shape != shape:
        raise HitogataError(f"skin_weights: shape {w.shape} given, expected (vertices, joints) = {shape}")
    if shape[1] > 65536:
        raise HitogataError(f"skin_weights: {shape[1]} joints given, at most 65536 fit JOINTS_0")
    w.sum_duplicates()
    w.eliminate_zeros()
    if not np.all(np.isfinite(w.data)) or np.any(w.data < 0):
        raise HitogataError("skin_weights: every weight must be finite and non-negative")
    n_vertices = shape[0]
    rows = np.repeat(np.arange(n_vertices), np.diff(w.indptr))  # already sorted (CSR)
    order = np.lexsort((w.indices, -w.data, rows))  # rows stay in place: rows[order] == rows
    rank = np.arange(len(order)) - w.indptr[rows]  # position of each entry within its row
    keep = rank < max_influences
    slot_rows, slots, entries = rows[keep], rank[keep], order[keep]

    joints = np.zeros((n_vertices, max_influences), dtype=np.uint16)
    weights = np.zeros((n_vertices, max_influences), dtype=np.float64)
    joints[slot_rows, slots] = w.indices[entries]
    weights[slot_rows, slots] = w.data[entries]
    total = weights.sum(axis=1)
    unbound = np.flatnonzero(total <= 0)
    if len(unbound):
        raise HitogataError(
            f"skin_weights: vertex {unbound[0]} (of {len(unbound)}) has no positive weight; "
            "every vertex must be bound to a joint"
        )
    single = (weights / total[:, None]).astype(np.float32)
    # Put the float32 rounding residue on the largest weight so each row sums to 1.
    single[:, 0] = (1.0 - single[:, 1:].astype(np.float64).sum(axis=1)).astype(np.float32)
    return joints, single


def _finite_array(name: str, value: Any, shape: tuple[int | None, ...]) -> np.ndarray:
    """``value`` as a finite float64 array of the given shape (None = any length)."""
    array = np.asarray(value, dtype=np.float64)
    if array.ndim != len(shape) or any(s is not None and s != a for s, a in zip(shape, array.shape)):
        wanted = "(" + ", ".join("N" if s is None else str(s) for s in shape) + ")"
        raise HitogataError(f"{name}: shape {array.shape} given, expected {wanted}")
    if not np.all(np.isfinite(array)):
        raise HitogataError(f"{name}: contains NaN or infinite values")
    return array


def _face_array(faces: Any, n_vertices: int) -> np.ndarray:
    faces = np.asarray(faces)
    if faces.ndim != 2 or faces.shape[1] != 3 or not np.issubdtype(faces.dtype, np.integer) or len(faces) == 0:
        raise HitogataError(f"faces: shape {faces.shape} dtype {faces.dtype} given, expected (F>0, 3) integers")
    if faces.min() < 0 or faces.max() >= n_vertices:
        raise HitogataError(f"faces: vertex indices must lie in [0, {n_vertices}), got [{faces.min()}, {faces.max()}]")
    return faces.astype(np.int64)


def _parent_array(parents: Any, n_joints: int) -> np.ndarray:
    """Validate a parent list: indices in [-1, J), no self-parents, no cycles."""
    parents = np.asarray(parents)
    if parents.shape != (n_joints,) or not np.issubdtype(parents.dtype, np.integer):
        raise HitogataError(f"joint_parents: shape {parents.shape} given, expected ({n_joints},) integers")
    parents = parents.astype(np.int64)
    if np.any(parents < -1) or np.any(parents >= n_joints):
        raise HitogataError(f"joint_parents: indices must lie in [-1, {n_joints}), got [{parents.min()}, {parents.max()}]")
    ancestor = parents.copy()
    for _ in range(n_joints):  # after J steps up, every chain must have left the tree
        ancestor = np.where(ancestor >= 0, parents[ancestor], -1)
    if np.any(ancestor >= 0):
        raise HitogataError(f"joint_parents: joint {np.flatnonzero(ancestor >= 0)[0]} is in a parent cycle")
    return parents


def _unit_normals(normals: Any, n_vertices: int) -> np.ndarray:
    normals = _finite_array("normals", normals, (n_vertices, 3))
    length = np.linalg.norm(normals, axis=1)
    if np.any(length == 0):
        raise HitogataError(f"normals: vertex {np.flatnonzero(length == 0)[0]} has a zero normal")
    return normals / length[:, None]
