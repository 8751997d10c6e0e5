"""The MakeHuman default rig (163 bones) placed on a body.

Joint positions follow the shape: each bone's head and tail is a fixed linear
combination of vertices (joint cubes, single vertices or means), so placing the
rig is one sparse product. The knees are the exception: MPFB2's height targets
move the knee joint cubes wrongly (6–7 cm off at extreme heights), so each knee
is instead regressed from the skin ring round it (`knee_regressor`).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import numpy as np
import scipy.sparse as sp

from hitogata.body.assets import Assets

KNEE_BONES = {"L": ("upperleg02.L", "lowerleg01.L"), "R": ("upperleg02.R", "lowerleg01.R")}
KNEE_RING_HALF_HEIGHT = 0.03  # m: skin within this height of the knee joint forms its ring
KNEE_RING_RADIUS = 0.12  # m: and within this horizontal distance of it


@dataclass(frozen=True)
class Rig:
    """Bone names, hierarchy and rest positions (metres, body frame)."""

    names: tuple[str, ...]
    parents: np.ndarray  # (B,) -1 for the root
    heads: np.ndarray  # (B, 3) joint centres
    tails: np.ndarray  # (B, 3)

    def index(self, name: str) -> int:
        """Position of a bone in `names`."""
        return self.names.index(name)

    @property
    def lengths(self) -> np.ndarray:
        return np.linalg.norm(self.tails - self.heads, axis=1)


def knee_regressor(assets: Assets, side: str) -> sp.csr_matrix:
    """A row (1, N) placing one knee joint as an affine combination of its skin ring.

    On the base mesh, where the knee cube is right, the minimum-norm weights that
    reproduce the knee from the ring's vertices (summing to 1) are found; any other
    shape then places its knee with the same weights, so the knee keeps its place
    relative to the skin round it whatever the height targets do to the cube.
    """
    base = assets.base_vertices
    head_row = assets.bone_names.index(KNEE_BONES[side][1])
    knee = assets.joint_regressor[head_row] @ base
    skin = base[: assets.n_surface]
    near = (np.abs(skin[:, 1] - knee[0, 1]) < KNEE_RING_HALF_HEIGHT) & (
        np.hypot(skin[:, 0] - knee[0, 0], skin[:, 2] - knee[0, 2]) < KNEE_RING_RADIUS
    )
    ring = np.flatnonzero(near)
    system = np.vstack([skin[ring].T, np.ones(len(ring))])
    rhs = np.append(knee[0], 1.0)
    weights = system.T @ np.linalg.solve(system @ system.T, rhs)
    return sp.csr_matrix((weights, (np.zeros(len(ring), dtype=int), ring)), shape=(1, len(base)))


@cache
def rig_regressor(assets: Assets) -> sp.csr_matrix:
    """The (2B, N) matrix giving heads then tails from all vertices, knees mended."""
    rows = assets.joint_regressor.tolil()
    n_bones = len(assets.bone_names)
    for side, (upper, lower) in KNEE_BONES.items():
        knee = knee_regressor(assets, side)
        rows[n_bones + assets.bone_names.index(upper)] = knee  # tail of the thigh
        rows[assets.bone_names.index(lower)] = knee  # head of the shank
    return rows.tocsr()


def place_rig(assets: Assets, vertices: np.ndarray) -> Rig:
    """The rig on a body whose vertices (all N, metres, body frame) are given."""
    ends = rig_regressor(assets) @ vertices
    n_bones = len(assets.bone_names)
    return Rig(
        names=assets.bone_names,
        parents=assets.bone_parents,
        heads=ends[:n_bones],
        tails=ends[n_bones:],
    )


# The rig's joint centres in a posture given by per-part rigid transforms.
#
# `measure` locates its planes with the MakeHuman rig's joint centres (bone
# heads). A posing code that moves a different set of parts (the 65-part
# skeleton) gives each part a skinning transform x ↦ R x + t; every rig joint
# centre then follows the part whose rest joint centre is nearest to it. Where
# the two coincide (shoulder, elbow, hip, knee, neck joints) the result is exact,
# since a joint centre moves alike with both parts that meet there; rig joints
# between vertebrae follow their nearest vertebra.


def carrying_parts(rest_heads: np.ndarray, part_joints: np.ndarray) -> np.ndarray:
    """(B,) for each rig joint centre (B, 3), the part whose rest joint centre (N, 3) is nearest."""
    rest_heads = np.asarray(rest_heads, dtype=np.float64)
    part_joints = np.asarray(part_joints, dtype=np.float64)
    return np.argmin(np.linalg.norm(rest_heads[:, None, :] - part_joints[None, :, :], axis=2), axis=1)


def carried_heads(
    rest_heads: np.ndarray, parts: np.ndarray, rotations: np.ndarray, translations: np.ndarray
) -> np.ndarray:
    """(..., B, 3) rig joint centres moved by their carrying parts' (`carrying_parts`) transforms,
    rotations (..., N, 3, 3) and translations (..., N, 3): one posture or a batch of them."""
    rotations, translations = np.asarray(rotations), np.asarray(translations)
    rest = np.asarray(rest_heads, dtype=np.float64)
    return np.einsum("...bij,bj->...bi", rotations[..., parts, :, :], rest) + translations[..., parts, :]


def posed_rig_heads(
    rest_heads: np.ndarray, part_joints: np.ndarray, rotations: np.ndarray, translations: np.ndarray
) -> np.ndarray:
    """(B, 3) posed rig joint centres from rest ones (B, 3), the parts' rest joint centres
    (N, 3) and their skinning rotations (N, 3, 3) and translations (N, 3)."""
    return carried_heads(rest_heads, carrying_parts(rest_heads, part_joints), rotations, translations)
