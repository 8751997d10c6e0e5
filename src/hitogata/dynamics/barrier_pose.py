"""The elastic skin of one held posture with its self-contact resolved as a barrier problem
(`hitogata.geometry.barrier_contact`, IPC): a study beside `elastic_pose(..., contact=True)`.

The barrier needs a start free of crossings and a path to the posture: the rest skin, the skin
skinned at `STEPS` even fractions of the posture's joint angles (the same skinning as the elastic
body), then the elastic skin itself. Needs the optional `ipctk` (the `contact` extra).
"""

from __future__ import annotations

import numpy as np

from hitogata.dynamics.contact import GROUPS
from hitogata.dynamics.single_pose import ElasticPose
from hitogata.geometry.barrier_contact import BarrierResult, barrier_resolve

STEPS = 4  # skinned postures on the way from rest to the posture
# groups whose skin may fold onto itself (a crease: skin far apart at rest meets); a hand's, a foot's and
# the head's small triangles lie close everywhere and stay held in shape by their bones
FOLDING = tuple(g for g, name in enumerate(GROUPS) if not name.startswith(("hand", "foot", "head")))


def barrier_skin(pose: ElasticPose, steps: int = STEPS) -> BarrierResult:
    """The posture's elastic skin with no part passing into another (coarse skin, (V, 3) in `.vertices`)."""
    dynamics = pose.dynamics
    fractions = np.arange(1, steps + 1)[:, None] / steps
    skinned = dynamics.poser.pose_many(fractions * pose.posed.angles, dynamics.rig.method)
    return barrier_resolve([dynamics.poser.body.vertices, *skinned, pose.vertices], dynamics.contact, folding=FOLDING)
