"""What the viewer shows at one moment: a skin surface, its skeleton's pose and the rig's joint centres.

A frame comes from the muscle sliders (a `PosedBody`) or from a sequence
frame; the scene, the measurements, the strain colours and the exports all
read frames, so they work alike for both.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.made_to_measure.scan_fit.closest import signed_distances
from hitogata.posing.pose import PosedBody, Poser
from hitogata.skeleton.kinematics import Pose
from hitogata.skeleton.placement import Skeleton
from hitogata.viewer.player import Sequence


@dataclass(frozen=True, eq=False)
class Frame:
    """One shown surface (V, 3), the 65-part pose when known, the rig joint centres (B, 3)."""

    vertices: np.ndarray
    pose: Pose | None
    rig_joints: np.ndarray

    def bones(self, reach: np.ndarray | None = None) -> np.ndarray | None:
        """(N, 2, 3) each part from its joint centre towards its tail, when the pose is known: the whole
        way, or the share `reach` (N,) of it (see `bone_reach`)."""
        if self.pose is None:
            return None
        heads, tails = self.pose.joints[0], self.pose.tails[0]
        if reach is not None:
            tails = heads + reach[:, None] * (tails - heads)
        return np.stack([heads, tails], axis=1)


def bone_reach(skeleton: Skeleton, vertices: np.ndarray, faces: np.ndarray, clearance: float,
               samples: int = 41) -> np.ndarray:
    """(N,) the share of each part, from its joint centre towards its tail, that lies under the rest skin:
    up to the last of `samples` points along it that is `clearance` (m) deep with none outside before it.

    The skeleton's last parts end on the skin or beyond it (the skull's and the jaw's tails at the
    crown and the chin, the distal phalanges' at the fingertips, the toes'); drawn the whole way,
    their lines poke through. Posing moves the skin and the parts together, so the share holds.
    """
    s = np.linspace(0.0, 1.0, samples)
    points = skeleton.joints[:, None] + s[None, :, None] * (skeleton.tails - skeleton.joints)[:, None]
    depth = -signed_distances(vertices, faces, points.reshape(-1, 3)).reshape(len(points), samples)
    covered = np.cumprod(depth > 0.0, axis=1).astype(bool) & (depth >= clearance)
    last = samples - 1 - np.argmax(covered[:, ::-1], axis=1)
    return np.where(covered.any(axis=1), s[last], 0.0)


def posed_frame(posed: PosedBody) -> Frame:
    """The frame of a body posed by its muscles."""
    return Frame(posed.vertices, posed.pose, posed.rig_joints)


def sequence_frame(poser: Poser, seq: Sequence, index: int) -> Frame:
    """Frame `index` of a sequence; its skeleton and rig joints from the sequence's angles when given."""
    vertices = np.asarray(seq.vertices[index], dtype=np.float64)
    pose = None if seq.angles is None else poser.kinematics.pose(seq.angles[index])
    if seq.joints is not None:
        joints = seq.joints[index]
    elif pose is not None:
        joints = poser.rig_joints(pose.rotations[0], pose.translations[0])
    else:
        joints = poser.body.rig.heads  # a surface deformed without moving the skeleton
    return Frame(vertices, pose, joints)
