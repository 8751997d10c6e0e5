"""BVH motion onto the 65-part skeleton (retargeting), and the skeleton's motion as BVH.

Import. The file's joints move in its own world (any up axis, facing, unit,
channel order). For each mapped BVH joint J with world rotation B_J(t):

- the file's frame G: the rotation taking hitogata's body frame (left =
  right hip → left hip, up = pelvis → head joint) to the file's rest frame
  (the same joints in the file): any up axis and facing;
- the rest pose's difference Q_J: the rotation taking J's rest bone
  directions in hitogata (to the parts its mapped children drive; a leaf:
  to its tail) onto the file's rest directions — the least-squares rotation
  when several children fix it (a spine joint with neck and shoulders), the
  shortest arc when one bone does: a BVH stores no twist about a bone at rest;
- the part's posed world rotation is then R_J = Gᵀ B_J Q_J; a chain of parts
  shares the rotation relative to J's mapped parent equally;
- each part's joint rotation relative to its parent's achieved rotation is
  fitted by its DOFs (least squares on the rotation matrix, a 1-DOF knee
  takes the rotation's part about its hinge); parts no joint drives stay at rest.

The root (pelvis) moves rigidly: rotation Gᵀ B_root G, translation scaled by
the ratio of the hip heights (the body's to the file's skeleton's, so a
walk's stride suits the body), horizontally from the first frame, vertically
from the floor (the first frame's lowest joint). The length unit thus never
matters for the angles or the root; it is detected for the report.

Export writes all 65 parts, rest = hitogata's rest pose, offsets in cm,
channels Zrotation Xrotation Yrotation (the root also Xposition Yposition
Zposition, absolute), each part's joint rotation as it is: importing that
file back gives the same joint angles.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from hitogata.errors import HitogataError
from hitogata.motion.bvh import Bvh, BvhJoint
from hitogata.motion.clip import MotionClip
from hitogata.motion.joint_map import JointMap, bare
from hitogata.skeleton.kinematics import Kinematics
from hitogata.geometry.rotations import axis_rotations, shortest_arc
from hitogata.skeleton.placement import Skeleton

UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001, "in": 0.0254}
STATURE_RANGE = (1.0, 2.4)  # m: a skeleton this tall (head joint above the lowest joint, ÷ 0.87) is an adult
EXPORT_CHANNELS = ("Zrotation", "Xrotation", "Yrotation")
FIT_ITERATIONS = 60


@dataclass(frozen=True)
class Retargeted:
    """The motion on our skeleton and what was found about the file."""

    clip: MotionClip
    unit: str | None  # detected (or given) length unit; None: not recognisable
    height: float  # the file's skeleton, head joint above the lowest joint, in its units
    mapped: tuple[str, ...]  # BVH joints that drove parts
    fit_error: float  # largest angle (rad) between a part's wanted and achieved rotation


def detect_unit(height: float) -> str | None:
    """The unit in which an adult's head joint stands `height` above the lowest joint, if only one fits."""
    fits = [u for u, scale in UNITS.items()
            if STATURE_RANGE[0] <= height * scale / 0.87 <= STATURE_RANGE[1]]
    return fits[0] if len(fits) == 1 else None


def retarget(bvh: Bvh, skeleton: Skeleton, joint_map: JointMap, unit: str | None = None) -> Retargeted:
    """Joint angles and root motion of our skeleton following the BVH's motion."""
    names = [bare(n) for n in bvh.names]
    index = {n: k for k, n in enumerate(names)}
    if joint_map.root not in index:
        raise HitogataError(f"{bvh.source}: joint map {joint_map.source}: root {joint_map.root!r} is not a BVH joint")
    mapped = [n for n in joint_map.chains if n in index]
    if not mapped:
        raise HitogataError(f"{bvh.source}: no BVH joint is in the joint map {joint_map.source}")
    if unit is not None and unit not in UNITS:
        raise HitogataError(f"unit {unit!r}: allowed {', '.join(UNITS)}")
    rest = bvh.rest_positions()
    size = float(np.ptp(np.vstack([rest, _rest_points(bvh, rest)]), axis=0).max())
    if not size > 0:
        raise HitogataError(f"{bvh.source}: every joint's OFFSET is zero; allowed a skeleton whose joints lie apart")
    rotations, positions = bvh.world()
    root = index[joint_map.root]
    part_of = {j: joint_map.chains[j] for j in mapped}
    owner = {p: j for j, parts in part_of.items() for p in parts}

    g = _pelvis_frame_rotation(bvh, index, joint_map, skeleton, rest)
    up_file = g @ np.array([0.0, 1.0, 0.0])
    ends = _rest_points(bvh, rest)
    height = float((rest @ up_file).max() - (ends @ up_file).min())
    unit = unit if unit is not None else detect_unit(height)

    # the rest-pose difference of each mapped joint, in the file's world
    mapped_children = _mapped_children(bvh, names, set(mapped))
    q = {}
    for j in mapped:
        k = index[j]
        theirs, ours = [], []
        for child in mapped_children[k]:
            theirs.append(rest[child] - rest[k])
            ours.append(skeleton.joints[skeleton.index(part_of[names[child]][0])]
                        - skeleton.joints[skeleton.index(part_of[j][0])])
        if not theirs:
            leaf = bvh.joints[k].end_site if bvh.joints[k].end_site is not None else _first_child_offset(bvh, k)
            if leaf is None:
                q[j] = g
                continue
            last = skeleton.index(part_of[j][-1])
            theirs, ours = [leaf], [skeleton.tails[last] - skeleton.joints[skeleton.index(part_of[j][0])]]
        short = [k for k, v in enumerate(theirs) if np.linalg.norm(v) <= 1e-6 * size]
        if short:
            raise HitogataError(f"{bvh.source}: joint {j!r}: its bone at rest has zero length (OFFSET 0 0 0); "
                                "allowed joints that lie apart from their mapped children")
        q[j] = _align(np.array(ours) @ g.T, np.array(theirs)) @ g

    # wanted world rotations of the mapped joints, in our world
    gt = g.T
    wanted = {j: gt @ rotations[:, index[j]] @ q[j] for j in mapped}
    root_rotation = gt @ rotations[:, root] @ g
    parent_of = _mapped_parents(bvh, names, set(mapped))

    n_frames, n_dofs = bvh.frames, skeleton.n_dofs
    angles = np.zeros((n_frames, n_dofs))
    achieved = np.zeros((n_frames, len(skeleton.names), 3, 3))
    worst = 0.0
    for i, part in enumerate(skeleton.names):
        parent = skeleton.parents[i]
        base = root_rotation if parent < 0 else achieved[:, parent]
        if part not in owner:
            achieved[:, i] = base
            continue
        j = owner[part]
        chain = part_of[j]
        up = parent_of.get(j)
        above = wanted[up] if up else root_rotation
        step = Rotation.from_matrix(np.swapaxes(above, 1, 2) @ wanted[j]).as_rotvec()
        share = (chain.index(part) + 1) / len(chain)
        target = above @ Rotation.from_rotvec(step * share).as_matrix()
        local = np.swapaxes(base, 1, 2) @ target
        dofs = np.flatnonzero(skeleton.dof_parts == i)
        if len(dofs):
            angles[:, dofs] = fit_dofs(skeleton.dof_axes[dofs], local)
            local_fit = _product(skeleton.dof_axes[dofs], angles[:, dofs])
        else:
            local_fit = np.broadcast_to(np.eye(3), local.shape)
        achieved[:, i] = base @ local_fit
        worst = max(worst, float(_angle_between(achieved[:, i], target).max()))

    # the root's rigid motion, scaled to this body by the hip heights
    lowest_ours = float(min(skeleton.joints[:, 1].min(), skeleton.tails[:, 1].min()))
    hip_ours = float(skeleton.joints[0, 1]) - lowest_ours
    hip_file = float(rest[root] @ up_file - (ends @ up_file).min())
    if hip_file <= 0:
        raise HitogataError(f"{bvh.source}: the root joint {joint_map.root!r} is not above the feet at rest")
    scale = hip_ours / hip_file
    frame0 = _frame_points(bvh, rotations, positions, 0)
    floor = float((frame0 @ up_file).min())
    start = positions[0, root] - (positions[0, root] @ up_file - floor) * up_file
    moved = (positions[:, root] - start) @ gt.T * scale  # in our world
    pelvis = skeleton.joints[0]
    place = np.column_stack([pelvis[0] + moved[:, 0], lowest_ours + moved[:, 1], pelvis[2] + moved[:, 2]])
    transforms = np.tile(np.eye(4), (n_frames, 1, 1))
    transforms[:, :3, :3] = root_rotation
    transforms[:, :3, 3] = place - np.einsum("fij,j->fi", root_rotation, pelvis)
    clip = MotionClip(np.arange(n_frames) * bvh.frame_time, angles, transforms)
    return Retargeted(clip, unit, height, tuple(mapped), worst)


def fit_dofs(axes: np.ndarray, local: np.ndarray) -> np.ndarray:
    """(F, K) angles whose rotations about `axes` (K, 3), in order, best give `local` (F, 3, 3):
    Levenberg–Marquardt on the matrix entries, from the rest pose and from the previous frame."""
    best = _levenberg(axes, local, np.zeros((len(local), len(axes))))
    for _ in range(2):  # let a good answer carry to the next frame (large rotations, near-singular axes)
        warm = _levenberg(axes, local, np.vstack([best[:1], best[:-1]]))
        better = _misfit(axes, local, warm) < _misfit(axes, local, best) - 1e-12
        best[better] = warm[better]
    return best


def _levenberg(axes: np.ndarray, local: np.ndarray, start: np.ndarray) -> np.ndarray:
    theta, mu = start.copy(), np.full(len(local), 1e-3)
    k = len(axes)
    for _ in range(FIT_ITERATIONS):
        factors = axis_rotations(axes, theta)  # (F, K, 3, 3)
        residual = (_chain(factors) - local).reshape(len(local), 9)
        jac = np.empty((len(local), 9, k))
        for j in range(k):
            left = _chain(factors[:, :j]) if j else np.eye(3)
            right = _chain(factors[:, j:])
            jac[:, :, j] = (left @ _skew(axes[j]) @ right).reshape(len(local), 9)
        jtj = np.swapaxes(jac, 1, 2) @ jac
        grad = np.einsum("fij,fi->fj", jac, residual)
        step = np.linalg.solve(jtj + mu[:, None, None] * np.eye(k), -grad[..., None])[..., 0]
        trial = theta + step
        old = (residual ** 2).sum(axis=1)
        new = ((_product(axes, trial) - local).reshape(len(local), 9) ** 2).sum(axis=1)
        good = new <= old
        theta[good] = trial[good]
        mu = np.where(good, mu * 0.3, mu * 10.0)
        if np.abs(step).max() < 1e-12:
            break
    return theta


def _misfit(axes: np.ndarray, local: np.ndarray, theta: np.ndarray) -> np.ndarray:
    return ((_product(axes, theta) - local) ** 2).sum(axis=(1, 2))


def _product(axes: np.ndarray, theta: np.ndarray) -> np.ndarray:
    return _chain(axis_rotations(axes, theta))


def _chain(factors: np.ndarray) -> np.ndarray:
    out = np.broadcast_to(np.eye(3), factors.shape[:1] + (3, 3)).copy()
    for j in range(factors.shape[1]):
        out = out @ factors[:, j]
    return out


def _skew(a: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def _angle_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    c = (np.trace(np.swapaxes(a, 1, 2) @ b, axis1=1, axis2=2) - 1.0) / 2.0
    return np.arccos(np.clip(c, -1.0, 1.0))


def _align(ours: np.ndarray, theirs: np.ndarray) -> np.ndarray:
    """The rotation taking unit directions `ours` (N, 3) onto `theirs`: shortest arc for one,
    least squares (Kabsch) for several."""
    a = ours / np.linalg.norm(ours, axis=1, keepdims=True)
    b = theirs / np.linalg.norm(theirs, axis=1, keepdims=True)
    if len(a) == 1 or np.linalg.matrix_rank(a, tol=1e-6) < 2:
        u, v = a.mean(axis=0), b.mean(axis=0)
        return shortest_arc(u / np.linalg.norm(u), v / np.linalg.norm(v))
    h = a.T @ b
    u, _, vt = np.linalg.svd(h)
    d = np.sign(np.linalg.det(vt.T @ u.T))
    return vt.T @ np.diag([1.0, 1.0, d]) @ u.T


def _pelvis_frame_rotation(bvh: Bvh, index: dict[str, int], joint_map: JointMap, skeleton: Skeleton,
                           rest: np.ndarray) -> np.ndarray:
    """G: our body frame (left, up, front) → the file's: left from the right to the left hip joint,
    up from the root to the head (both skeletons stand at rest, whatever their arms do)."""
    by_part = {parts[0]: j for j, parts in joint_map.chains.items() if j in index}
    missing = [p for p in ("thigh_l", "thigh_r", "head") if p not in by_part]
    if missing:
        raise HitogataError(f"{bvh.source}: joint map {joint_map.source}: no BVH joint drives {missing[0]!r}; "
                            "thigh_l, thigh_r and head are needed to find the file's up and left")
    joint = {p: skeleton.joints[skeleton.index(p)] for p in ("thigh_l", "thigh_r", "head")}
    ours = _frame(joint["thigh_l"] - joint["thigh_r"], joint["head"] - skeleton.joints[0])
    at = {p: rest[index[by_part[p]]] for p in ("thigh_l", "thigh_r", "head")}
    theirs = _frame(at["thigh_l"] - at["thigh_r"], at["head"] - rest[index[joint_map.root]])
    return theirs @ ours.T


def _frame(lateral: np.ndarray, up: np.ndarray) -> np.ndarray:
    x = lateral / np.linalg.norm(lateral)
    y = up - (up @ x) * x
    y /= np.linalg.norm(y)
    return np.column_stack([x, y, np.cross(x, y)])


def _mapped_children(bvh: Bvh, names: list[str], mapped: set[str]) -> dict[int, list[int]]:
    """For each joint, its nearest mapped descendants."""
    out: dict[int, list[int]] = {k: [] for k in range(len(names))}
    for k in range(len(names)):
        if names[k] not in mapped:
            continue
        p = bvh.joints[k].parent
        while p >= 0 and names[p] not in mapped:
            p = bvh.joints[p].parent
        if p >= 0:
            out[p].append(k)
    return out


def _mapped_parents(bvh: Bvh, names: list[str], mapped: set[str]) -> dict[str, str | None]:
    out = {}
    for k, n in enumerate(names):
        if n in mapped:
            p = bvh.joints[k].parent
            while p >= 0 and names[p] not in mapped:
                p = bvh.joints[p].parent
            out[n] = names[p] if p >= 0 else None
    return out


def _first_child_offset(bvh: Bvh, k: int) -> np.ndarray | None:
    for j in bvh.joints:
        if j.parent == k and np.linalg.norm(j.offset) > 0:
            return j.offset
    return None


def _rest_points(bvh: Bvh, rest: np.ndarray) -> np.ndarray:
    """Joints and end sites at rest."""
    sites = [rest[k] + j.end_site for k, j in enumerate(bvh.joints) if j.end_site is not None]
    return np.vstack([rest, *sites]) if sites else rest


def _frame_points(bvh: Bvh, rotations: np.ndarray, positions: np.ndarray, f: int) -> np.ndarray:
    sites = [positions[f, k] + rotations[f, k] @ j.end_site for k, j in enumerate(bvh.joints)
             if j.end_site is not None]
    return np.vstack([positions[f], *sites]) if sites else positions[f]


def export_bvh(skeleton: Skeleton, clip: MotionClip, source: str = "<export>") -> Bvh:
    """The skeleton's motion as BVH: every part a joint, hitogata's rest pose, centimetres."""
    kin = Kinematics(skeleton)
    local = kin.local_transforms(clip.angles)[:, :-1, :3, :3]  # (F, N, 3, 3), rest-world frame
    joints, columns = [], []
    children = {i: [c for c, p in enumerate(skeleton.parents) if p == i] for i in range(len(skeleton.names))}
    for i, name in enumerate(skeleton.names):
        parent = int(skeleton.parents[i])
        offset = (skeleton.joints[i] - (skeleton.joints[parent] if parent >= 0 else 0.0)) * 100.0
        end = (skeleton.tails[i] - skeleton.joints[i]) * 100.0 if not children[i] else None
        channels = (("Xposition", "Yposition", "Zposition") if parent < 0 else ()) + EXPORT_CHANNELS
        joints.append(BvhJoint(name, parent, offset, channels, end))
        rot = clip.root[:, :3, :3] @ local[:, i] if parent < 0 else local[:, i]
        euler = Rotation.from_matrix(rot).as_euler("ZXY", degrees=True)
        if parent < 0:
            place = np.einsum("fij,j->fi", clip.root[:, :3, :3], skeleton.joints[i]) + clip.root[:, :3, 3]
            columns.append(place * 100.0)
        columns.append(euler)
    frame_time = float(clip.times[1] - clip.times[0]) if len(clip.times) > 1 else 1.0 / 30.0
    return Bvh(source, tuple(joints), frame_time, np.hstack(columns))
