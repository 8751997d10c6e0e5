"""The shoulder complex: one clinical control per arm motion, the girdle following the humerus.

Clinical shoulder flexion and abduction (AAOS: 0…180°) are
motions of the humerus relative to the thorax, made by the glenohumeral
joint and the shoulder girdle together. `shoulder_l.flexion` and
`shoulder_l.abduction` (and `_r`) set the humerus's direction relative to the
thorax as the glenohumeral DOFs do from the anatomical position (flexion about
the body's side axis, outermost, then abduction in the frontal plane), and the
girdle follows by the scapulohumeral rhythm of Inman, Saunders & Abbott
("Observations on the function of the shoulder joint", JBJS 26, 1944): in the
first 30° of elevation (the setting phase) the glenohumeral joint moves alone;
above it glenohumeral and scapulothoracic motion go on together, to 120° + 60°
at full elevation (2 : 1 over the whole arc). Of the scapulothoracic part the
sternoclavicular joint gives a quarter (clavicle elevation, 15° at full
elevation; Inman's clavicle rises about 4° per 10° up to 90° and little
after) and the scapula's upward rotation three quarters (45°).

The glenohumeral angles are then solved so that the humerus points exactly
where the clinical angles say, its axial rotation unchanged. The skeleton's
scapula turns in the frontal plane only (one DOF), so in forward flexion
between about 130° and 170° the glenohumeral flexion/abduction angles leave
their single-joint ranges by up to about 20°; the complex is checked against
its own clinical range instead (`CHANNEL_RANGES`).
"""

from __future__ import annotations

import math

import numpy as np

from hitogata.errors import HitogataError
from hitogata.skeleton.kinematics import Kinematics
from hitogata.geometry.rotations import axis_rotations
from hitogata.skeleton.placement import Skeleton

SIDES = ("l", "r")
MOTIONS = ("flexion", "abduction")
# Clinical ranges of the shoulder complex (thoracohumeral), degrees: AAOS flexion and abduction
# 180°; extension 40°, the glenohumeral joint's (AAOS 60° needs the scapula's tilt, not modelled).
CHANNEL_RANGES = {"flexion": (-40.0, 180.0), "abduction": (0.0, 180.0)}
SETTING_PHASE = math.radians(30.0)  # glenohumeral alone below this elevation (Inman 1944)
FULL_ELEVATION = math.radians(180.0)
SCAPULOTHORACIC_FULL = math.radians(60.0)  # at full elevation: 120° glenohumeral + 60°
CLAVICLE_SHARE = 0.25  # of the scapulothoracic rotation; the scapula's upward rotation gives the rest


def channel_names(skeleton: Skeleton) -> tuple[str, ...]:
    """The shoulder-complex controls a skeleton has ('shoulder_l.flexion', ...)."""
    return tuple(f"shoulder_{s}.{m}" for s in SIDES if _has_girdle(skeleton, s) for m in MOTIONS)


def _has_girdle(skeleton: Skeleton, side: str) -> bool:
    names = set(skeleton.dof_names)
    return {
        f"clavicle_{side}.elevation",
        f"scapula_{side}.upward_rotation",
        f"upper_arm_{side}.flexion",
        f"upper_arm_{side}.abduction",
    } <= names


def girdle_dofs(skeleton: Skeleton, side: str) -> tuple[int, int, int, int]:
    """Indices of the DOFs a shoulder control sets: clavicle elevation, scapula rotation, GH flexion, GH abduction."""
    k = skeleton.dof_index
    return (
        k(f"clavicle_{side}.elevation"),
        k(f"scapula_{side}.upward_rotation"),
        k(f"upper_arm_{side}.flexion"),
        k(f"upper_arm_{side}.abduction"),
    )


def scapulothoracic(elevation: float) -> float:
    """The girdle's rotation (radians) at a thoracohumeral elevation (radians), Inman's rhythm."""
    share = (elevation - SETTING_PHASE) / (FULL_ELEVATION - SETTING_PHASE)
    return SCAPULOTHORACIC_FULL * float(np.clip(share, 0.0, 1.0))


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    return axis_rotations(axis[None], np.array([angle]))[0]


def shoulder_pose(
    kinematics: Kinematics, angles: np.ndarray, side: str, flexion: float, abduction: float
) -> np.ndarray:
    """Rest-relative angles with one arm's girdle and glenohumeral DOFs set from clinical
    thoracohumeral flexion and abduction (radians); other DOFs (the clavicle's protraction,
    the humerus's axial rotation) as in `angles`."""
    sk = kinematics.skeleton
    kc, ks, kf, ka = girdle_dofs(sk, side)
    arm = sk.index(f"upper_arm_{side}")
    axis_f, axis_a = sk.dof_axes[kf], sk.dof_axes[ka]
    along = sk.tails[arm] - sk.joints[arm]
    along = along / np.linalg.norm(along)
    target = _rotation(axis_f, flexion) @ _rotation(axis_a, abduction - sk.rest[ka]) @ along
    # the elevation from the hanging arm: the angle between the arm turned by both and the vertical
    girdle = scapulothoracic(math.acos(float(np.clip(math.cos(flexion) * math.cos(abduction), -1.0, 1.0))))
    q = np.array(angles, dtype=float)
    q[kc] = CLAVICLE_SHARE * girdle - sk.rest[kc]
    q[ks] = (1.0 - CLAVICLE_SHARE) * girdle - sk.rest[ks]
    local = kinematics.local_transforms(q[None])[0, :, :3, :3]
    rotated = local[sk.index(f"clavicle_{side}")] @ local[sk.index(f"scapula_{side}")]
    q[kf], q[ka] = _glenohumeral(sk, kf, ka, along, rotated.T @ target)
    return q


def _glenohumeral(sk: Skeleton, kf: int, ka: int, along: np.ndarray, direction: np.ndarray) -> tuple[float, float]:
    """Flexion and abduction (rest-relative) turning the rest humerus `along` onto `direction`
    (in the girdle's rest frame): of the two solutions, the one nearer the joint's ranges."""
    axis_f, axis_a = sk.dof_axes[kf], sk.dof_axes[ka]
    # the component along the flexion axis is set by the abduction alone: P cos a + Q sin a + C
    c = (axis_a @ along) * (axis_a @ axis_f)
    p, s = along @ axis_f - c, np.cross(axis_a, along) @ axis_f
    phase = math.atan2(s, p)
    spread = math.acos(float(np.clip((direction @ axis_f - c) / math.hypot(p, s), -1.0, 1.0)))
    best: tuple[float, float, float] | None = None
    for a in (phase + spread, phase - spread):
        a = (a + math.pi) % (2 * math.pi) - math.pi
        u = _rotation(axis_a, a) @ along
        u_perp, d_perp = u - (u @ axis_f) * axis_f, direction - (direction @ axis_f) * axis_f
        f = math.atan2(float(axis_f @ np.cross(u_perp, d_perp)), float(u_perp @ d_perp))
        excess = sum(
            max(lo - x, x - hi, 0.0) for x, lo, hi in ((f, sk.lower[kf], sk.upper[kf]), (a, sk.lower[ka], sk.upper[ka]))
        )
        if best is None or excess < best[0] - 1e-9:
            best = (excess, f, a)
    if best is None:  # the loop above always sets it: its first candidate is taken
        raise HitogataError("shoulder: no glenohumeral solution")
    return best[1], best[2]
