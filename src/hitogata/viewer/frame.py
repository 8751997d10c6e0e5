"""What the viewer shows at one moment: a skin surface, its skeleton's pose and the rig's joint centres.

A frame comes from the muscle sliders (a `PosedBody`) or from a sequence
frame; the scene, the measurements, the strain colours and the exports all
read frames, so they work alike for both.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.pose import PosedBody, Poser
from hitogata.skeleton.kinematics import Pose
from hitogata.viewer.player import Sequence


@dataclass(frozen=True, eq=False)
class Frame:
    """One shown surface (V, 3), the 65-part pose when known, the rig joint centres (B, 3)."""

    vertices: np.ndarray
    pose: Pose | None
    rig_joints: np.ndarray

    @property
    def bones(self) -> np.ndarray | None:
        """(N, 2, 3) each part from its joint centre to its tail, when the pose is known."""
        if self.pose is None:
            return None
        return np.stack([self.pose.joints[0], self.pose.tails[0]], axis=1)


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
