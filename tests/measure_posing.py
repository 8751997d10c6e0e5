"""A stand-in for the posing code in tests: bend one joint with linear blend skinning.

The vertices beyond the joint follow a rotation about the joint centre in
proportion to their summed skin weights on the moving bones (the rest of the
body stays put). `flex_elbow` gives the same surface, to rounding, as
`hitogata.pose.pose_body(body, clinical={"forearm_r.flexion": angle})` with
linear blend skinning; the tests keep this stand-in until the posing code lands.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from hitogata.body import Body

FOREARM_PREFIXES = ("lowerarm01", "lowerarm02", "wrist", "metacarpal", "finger")
LEG_PREFIXES = ("upperleg01", "upperleg02", "lowerleg01", "lowerleg02", "foot", "toe")


def bend(body: Body, joint: str, hinge: np.ndarray, angle: float, prefixes: tuple[str, ...], side: str):
    """Vertices and joint centres with the `side` bones named by `prefixes` turned by `angle`
    (radians, right-handed about `hinge`) round the head of bone `joint`."""
    rig = body.rig
    centre = rig.heads[rig.index(joint)]
    turn = Rotation.from_rotvec(angle * hinge / np.linalg.norm(hinge)).as_matrix()
    moving = [i for i, name in enumerate(rig.names) if name.endswith(f".{side}") and name.startswith(prefixes)]
    weight = np.asarray(body.skin_weights[:, moving].sum(axis=1)).ravel()[:, None]
    rotated = (body.vertices - centre) @ turn.T + centre
    joints = rig.heads.copy()
    joints[moving] = (joints[moving] - centre) @ turn.T + centre
    return (1.0 - weight) * body.vertices + weight * rotated, joints


def elbow_flexion_rest(body: Body, side: str = "R") -> float:
    """The rest pose's elbow flexion, radians (0 = straight arm)."""
    heads = body.rig.heads
    upper = heads[body.rig.index(f"lowerarm01.{side}")] - heads[body.rig.index(f"upperarm01.{side}")]
    fore = heads[body.rig.index(f"wrist.{side}")] - heads[body.rig.index(f"lowerarm01.{side}")]
    cos = upper @ fore / np.linalg.norm(upper) / np.linalg.norm(fore)
    return float(np.arccos(np.clip(cos, -1.0, 1.0)))


def flex_elbow(body: Body, flexion: float, side: str = "R") -> tuple[np.ndarray, np.ndarray]:
    """Vertices and joint centres with the elbow flexed to `flexion` radians (0 = straight),
    about the normal of the plane of the rest pose's bent arm."""
    heads = body.rig.heads
    elbow = heads[body.rig.index(f"lowerarm01.{side}")]
    upper = elbow - heads[body.rig.index(f"upperarm01.{side}")]
    fore = heads[body.rig.index(f"wrist.{side}")] - elbow
    hinge = np.cross(upper, fore)
    return bend(body, f"lowerarm01.{side}", hinge, flexion - elbow_flexion_rest(body, side), FOREARM_PREFIXES, side)


def flex_hip(body: Body, flexion: float, side: str = "R") -> tuple[np.ndarray, np.ndarray]:
    """Vertices and joint centres with the thigh raised forwards by `flexion` radians."""
    return bend(body, f"upperleg01.{side}", np.array([-1.0, 0.0, 0.0]), flexion, LEG_PREFIXES, side)
