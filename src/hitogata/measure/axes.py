"""Body axes from joint positions: where girth planes point in any posture.

A trunk girth (chest, waist, hip) is horizontal in the standing rest pose
(ISO 8559-1). When the body bends, its plane should turn with the part it
goes round, so its normal is the rest vertical carried by that part's frame:
n = R_posed R_restᵀ ŷ, with each frame built from joint centres. Limb and neck
girths are perpendicular to the limb's or the neck's long axis instead.
"""

from __future__ import annotations

import numpy as np

UP = np.array([0.0, 1.0, 0.0])

# Trunk segment → (joint pair along its long axis, joint pair across it, left minus right).
TRUNK_FRAMES = {
    "pelvis": (("root", "spine05"), ("upperleg01.R", "upperleg01.L")),
    "waist": (("spine04", "spine02"), ("upperleg01.R", "upperleg01.L")),
    "thorax": (("spine02", "neck01"), ("shoulder01.R", "shoulder01.L")),
}
# The pelvis has no up-pointing bone among the joint centres: its first pair
# points forward (root → spine05), so that frame is built from forward and lateral.
FORWARD_FIRST = {"pelvis"}


class JointSet:
    """Joint centres (B, 3) looked up by bone name (MakeHuman rig order)."""

    def __init__(self, names: tuple[str, ...], heads: np.ndarray) -> None:
        self._index = {name: i for i, name in enumerate(names)}
        self.heads = np.asarray(heads, dtype=np.float64)

    def __getitem__(self, name: str) -> np.ndarray:
        return self.heads[self._index[name]]


def unit(vector: np.ndarray) -> np.ndarray:
    return vector / np.linalg.norm(vector)


def axis(joints: JointSet, start: str, end: str) -> np.ndarray:
    """Unit vector from one joint centre to another."""
    return unit(joints[end] - joints[start])


def trunk_frame(joints: JointSet, segment: str) -> np.ndarray:
    """Rotation (3, 3), columns = the segment's lateral, up and forward axes in the body frame."""
    (a, b), (right, left) = TRUNK_FRAMES[segment]
    lateral = unit(joints[left] - joints[right])
    along = joints[b] - joints[a]
    along = unit(along - (along @ lateral) * lateral)
    if segment in FORWARD_FIRST:
        forward, up = along, np.cross(along, lateral)
    else:
        up, forward = along, np.cross(lateral, along)
    return np.stack([lateral, up, forward], axis=1)


def trunk_normal(rest: JointSet, posed: JointSet, segment: str) -> np.ndarray:
    """The rest pose's vertical carried by a trunk segment into the posture."""
    return trunk_frame(posed, segment) @ (trunk_frame(rest, segment).T @ UP)
