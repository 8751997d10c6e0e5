"""The extreme poses a garment is judged at: each joint at the end of its clinical range.

Clinical angles (radians, `Poser.pose(clinical=...)`) by pose name: elbow
150°, knee 135°, hip flexion 120°, both hips and knees at 90° (seated), hip
adduction 30° (the other leg abducted 30° out of the way), shoulder flexion 180° and abduction 170° (through the shoulder
complex: the girdle follows by the scapulohumeral rhythm), and the neck and
trunk with every segment at the end of its range (the AAOS regional ranges:
neck flexion 45°, trunk flexion 80°, trunk rotation 45°). The limbs are the
left ones. Used by the tests and the benchmarks that measure the skin there.
"""

from __future__ import annotations

import math

from hitogata.skeleton.combined import SPINE
from hitogata.skeleton.placement import Skeleton

NECK = tuple(f"cervical_{i}" for i in range(1, 8)) + ("head",)


def at_limit(skeleton: Skeleton, parts: tuple[str, ...], dof: str) -> dict[str, float]:
    """Clinical angles (radians) putting every segment of a region at the upper end of its range."""
    out = {}
    for part in parts:
        k = skeleton.dof_index(f"{part}.{dof}")
        out[f"{part}.{dof}"] = float(skeleton.rest[k] + skeleton.upper[k])
    return out


def extreme_poses(skeleton: Skeleton) -> dict[str, dict[str, float]]:
    """The extreme poses by name: clinical angles, radians."""
    d = math.radians
    return {
        "elbow 150°": {"forearm_l.flexion": d(150)},
        "knee 135°": {"shank_l.flexion": d(135)},
        "hip flexion 120°": {"thigh_l.flexion": d(120)},
        "seated 90/90": {"thigh_l.flexion": d(90), "thigh_r.flexion": d(90),
                         "shank_l.flexion": d(90), "shank_r.flexion": d(90)},
        # AAOS: the other leg abducted out of the way (one leg alone goes through the other: skeleton.combined)
        "hip adduction 30°": {"thigh_l.abduction": d(-30), "thigh_r.abduction": d(30)},
        "shoulder flexion 180°": {"shoulder_l.flexion": d(180)},
        "shoulder abduction 170°": {"shoulder_l.abduction": d(170)},
        "neck flexion 45°": at_limit(skeleton, NECK, "flexion"),
        "trunk flexion 80°": at_limit(skeleton, SPINE, "flexion"),
        "trunk rotation 45°": at_limit(skeleton, SPINE, "rotation"),
    }
