"""The 65-part skeleton (the paper's passive organ): list, placement, kinematics, weights."""

from hitogata.skeleton.kinematics import Kinematics, Pose, forward_kinematics, limit_violations
from hitogata.skeleton.placement import Skeleton, place_skeleton
from hitogata.skeleton.spec import SkeletonSpec, load_skeleton_spec
from hitogata.skeleton.weights import part_weights

__all__ = [
    "Kinematics",
    "Pose",
    "Skeleton",
    "SkeletonSpec",
    "forward_kinematics",
    "limit_violations",
    "load_skeleton_spec",
    "part_weights",
    "place_skeleton",
]
