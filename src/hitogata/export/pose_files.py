"""Write a posed body: a re-posable skinned GLB, or the posed surface as OBJ/PLY.

GLB: the rest skin bound to the 65 parts of the skeleton (joints = parts,
their hierarchy, the parts' skin weights, bind pose = rest pose), with the pose
written as each joint node's rotation relative to its parent. So Blender or
three.js open the file in the requested pose, can return it to rest, and can
re-pose it joint by joint — the file stays a model, not a frozen surface. A
viewer skins it linearly (glTF has only linear blend skinning) with the 4
largest weights per vertex: within a millimetre or so of hitogata's own LBS
surface; for DQS, write OBJ or PLY.

OBJ/PLY: the posed surface as hitogata skinned it (LBS or DQS).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from hitogata.errors import HitogataError
from hitogata.export.atomic import write_bytes_atomically
from hitogata.export.body_files import check_body_path
from hitogata.export.gltf import GlbBuilder, add_skinned_mesh
from hitogata.export.meshfiles import write_mesh
from hitogata.posing.pose import PosedBody, Poser
from hitogata.geometry.rotations import matrix_to_quaternion


def local_rotations(rotations: np.ndarray, parents: np.ndarray) -> np.ndarray:
    """(N, 3, 3) each part's rotation relative to its parent, from world rotations (N, 3, 3)."""
    parent = rotations[np.maximum(parents, 0)]
    local = np.einsum("nji,njk->nik", parent, rotations)
    local[parents < 0] = rotations[parents < 0]
    return local


def posed_glb_bytes(poser: Poser, posed: PosedBody, extras: Mapping[str, Any] | None = None) -> bytes:
    """The GLB file contents: rest skin on the 65-part skeleton, the pose as joint rotations."""
    sk = posed.skeleton
    builder = GlbBuilder()
    nodes = add_skinned_mesh(
        builder,
        poser.body.vertices,
        poser.body.faces,
        joint_names=sk.names,
        joint_parents=sk.parents,
        joint_positions=sk.joints,
        skin_weights=poser.skin.weights,
        name="hitogata posed body",
        extras=extras,
    )
    quaternions = matrix_to_quaternion(local_rotations(posed.pose.rotations[0], sk.parents))  # (w, x, y, z)
    for node, q in zip(nodes.joints, quaternions):
        if abs(abs(q[0]) - 1.0) > 1e-12:
            builder.gltf.nodes[node].rotation = [float(q[1]), float(q[2]), float(q[3]), float(q[0])]
    return builder.to_bytes()


def write_posed(
    path: str | os.PathLike, poser: Poser, posed: PosedBody, extras: Mapping[str, Any] | None = None
) -> Path:
    """Write a posed body; the format follows the suffix (.glb, .obj, .ply). Atomic."""
    path = check_body_path(path)
    if path.suffix.lower() != ".glb":
        return write_mesh(path, posed.vertices, posed.faces)
    return write_bytes_atomically(path, posed_glb_bytes(poser, posed, extras))


def check_posed_path(path: str | os.PathLike, skinning: str) -> Path:
    """The path, if a posed body can be written there with this skinning."""
    path = check_body_path(path)
    if path.suffix.lower() == ".glb" and skinning != "lbs":
        raise HitogataError(
            f"{path}: --skinning {skinning} cannot go in a GLB (glTF viewers skin linearly); write .obj or .ply"
        )
    return path
