"""The skeleton on a body: joint centres, part frames and joint axes at rest.

Joint centres come from the MakeHuman rig placed on the body (bone heads and
tails follow the shape), vertebrae from arc-length fractions along the rig's
spine chain. Each part's long axis runs from its joint centre to its tail.

A part's frame is either 'bone' — y along the bone, z the body's front made
perpendicular to it, x perpendicular to both, pointing to the body's left — or
'world' (the body's axes; for parts lying near the front or the side axis:
feet, toes, jaw, clavicles, pelvis). DOF axes are named in that frame ('x',
'-z', ...), or in the body's frame whatever the part's ('X', '-Z', ...: the
shoulder, whose rest pose is abducted, flexes in the body's sagittal plane),
plus 'long' (the bone) and 'hinge' (normal to the parent's and the part's long
axes, towards the body's left: the plane of a bent elbow).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.errors import HitogataError
from hitogata.body.rig import Rig
from hitogata.skeleton.spec import Anchor, SkeletonSpec

WORLD = {"x": np.array([1.0, 0.0, 0.0]), "y": np.array([0.0, 1.0, 0.0]), "z": np.array([0.0, 0.0, 1.0])}
MIN_PERPENDICULAR = 0.3  # sine of 17.5°: a reference axis nearer the bone than this is ill-defined
MIN_HINGE = 0.17  # sine of 10°: bones nearer parallel than this give no hinge plane


@dataclass(frozen=True, eq=False)
class Skeleton:
    """A skeleton list placed on one body, at rest (metres, radians, body frame).

    `frames[i]` is part i's rest orientation, a rotation (columns x, y, z: for
    'bone' parts y along the bone, z its front, x = y × z); `bases[i]` maps a
    point given in part units to metres from its joint (columns: the part's
    left, along, front axes — or the world axes — times the part's length).
    DOF limits `lower`/`upper` are relative to the rest pose (the joint angles
    FK takes); `rest` is the rest pose's clinical angle.
    """

    spec: SkeletonSpec
    names: tuple[str, ...]
    parents: np.ndarray  # (N,) -1 for the root
    joints: np.ndarray  # (N, 3)
    tails: np.ndarray  # (N, 3)
    frames: np.ndarray  # (N, 3, 3)
    bases: np.ndarray  # (N, 3, 3)
    dof_names: tuple[str, ...]
    dof_parts: np.ndarray  # (D,)
    dof_axes: np.ndarray  # (D, 3) unit, world at rest
    lower: np.ndarray  # (D,)
    upper: np.ndarray  # (D,)
    rest: np.ndarray  # (D,)

    @property
    def lengths(self) -> np.ndarray:
        """(N,) joint-to-tail distance of each part, metres."""
        return np.linalg.norm(self.tails - self.joints, axis=1)

    @property
    def n_dofs(self) -> int:
        return len(self.dof_names)

    def index(self, name: str) -> int:
        """Position of a part."""
        return self.spec.index(name)

    def dof_index(self, name: str) -> int:
        """Position of a 'part.dof' degree of freedom."""
        try:
            return self.dof_names.index(name)
        except ValueError:
            raise HitogataError(f"{self.spec.source}: no degree of freedom {name!r} (write 'part.dof')") from None

    def point(self, part: int, at: np.ndarray | tuple[float, float, float]) -> np.ndarray:
        """Rest position (metres) of a point given in part units."""
        return self.joints[part] + self.bases[part] @ np.asarray(at, dtype=float)

    def clinical(self, angles: np.ndarray) -> np.ndarray:
        """Clinical angles (0 = anatomical position) of rest-relative joint angles."""
        return np.asarray(angles) + self.rest


def chain_points(rig: Rig, first: str, last: str, where: str) -> np.ndarray:
    """Heads of the rig bones from `first` down to `last` (first must be an ancestor)."""
    k, path = rig.index(last), []
    while k >= 0:
        path.append(k)
        if rig.names[k] == first:
            return rig.heads[path[::-1]]
        k = int(rig.parents[k])
    raise HitogataError(f"{where}: bone {first!r} is not an ancestor of {last!r} in the rig")


def along_polyline(points: np.ndarray, fraction: float) -> np.ndarray:
    """The point at an arc-length fraction along a polyline."""
    seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    target = fraction * s[-1]
    k = int(np.clip(np.searchsorted(s, target, side="right") - 1, 0, len(seg) - 1))
    t = (target - s[k]) / seg[k] if seg[k] > 0 else 0.0
    return points[k] + t * (points[k + 1] - points[k])


def rig_point(rig: Rig, anchor: Anchor, where: str) -> np.ndarray:
    """Where an anchor (not of kind 'part') sits on this rig."""
    for name in anchor.names:
        if name not in rig.names:
            raise HitogataError(f"{where}: unknown rig bone {name!r}")
    if anchor.kind == "between":
        first, last = anchor.names  # a 'between' anchor names two bones (skeleton.spec checks)
        return along_polyline(chain_points(rig, first, last, where), anchor.fraction)
    ends = rig.heads if anchor.end == "head" else rig.tails
    return ends[[rig.index(n) for n in anchor.names]].mean(axis=0)


def bone_frame(long: np.ndarray, where: str) -> np.ndarray:
    """Columns (left, long, front) of a 'bone' frame: orthonormal, x towards +X.

    The front axis is the world front made perpendicular to the bone; a bone that
    runs near the front axis (an old body's forward-leaning upper neck) takes the
    world left axis made perpendicular instead.
    """
    z = WORLD["z"] - (WORLD["z"] @ long) * long
    if np.linalg.norm(z) >= MIN_PERPENDICULAR:
        z /= np.linalg.norm(z)
        x = np.cross(long, z)
    else:
        x = WORLD["x"] - (WORLD["x"] @ long) * long
        x /= np.linalg.norm(x)
        z = np.cross(x, long)
    if abs(x[0]) < MIN_PERPENDICULAR:
        raise HitogataError(f"{where}: the bone runs within 17° of the body's side axis; use frame = 'world'")
    return np.column_stack([x if x[0] > 0 else -x, long, z])


def resolve_axis(
    axis: str, basis: np.ndarray, long: np.ndarray, parent_long: np.ndarray | None, where: str
) -> np.ndarray:
    """A DOF axis name ('x', '-long', 'hinge', ...) as a world unit vector at rest."""
    sign, name = (-1.0, axis[1:]) if axis.startswith("-") else (1.0, axis)
    if name == "long":
        return sign * long
    if name in WORLD:
        return sign * basis[:, "xyz".index(name)]
    if name.lower() in WORLD:
        return sign * WORLD[name.lower()]
    if parent_long is None:
        raise HitogataError(f"{where}: axis {axis!r} needs a parent part")
    h = np.cross(parent_long, long)
    n = np.linalg.norm(h)
    if n < MIN_HINGE:
        raise HitogataError(f"{where}: axis {axis!r}: the part and its parent are within 10° of parallel")
    h /= n
    return sign * (h if h[0] >= 0 else -h)


def place_skeleton(spec: SkeletonSpec, rig: Rig) -> Skeleton:
    """Place a skeleton list on a rig (a body's `body.rig`)."""
    n = len(spec.parts)
    joints = np.array([rig_point(rig, p.joint, f"{spec.source}: part {p.name!r}: joint") for p in spec.parts])
    tails = np.empty((n, 3))
    for i, p in enumerate(spec.parts):
        if p.tail is None:  # the spec reader gives every part a tail
            raise HitogataError(f"{spec.source}: part {p.name!r}: no tail")
        if p.tail.kind == "part":
            tails[i] = joints[spec.index(p.tail.names[0])]
        else:
            tails[i] = rig_point(rig, p.tail, f"{spec.source}: part {p.name!r}: tail")
    longs = tails - joints
    norms = np.linalg.norm(longs, axis=1)
    for i, p in enumerate(spec.parts):
        if norms[i] < 1e-6:
            raise HitogataError(f"{spec.source}: part {p.name!r}: its tail sits on its joint centre (zero length)")
    longs /= norms[:, None]
    parents = np.array(spec.parents, dtype=np.int64)

    frames = np.empty((n, 3, 3))
    bases = np.empty((n, 3, 3))
    dof_parts, dof_axes, lower, upper, rest = [], [], [], [], []
    for i, p in enumerate(spec.parts):
        where = f"{spec.source}: part {p.name!r}"
        basis = np.eye(3) if p.frame == "world" else bone_frame(longs[i], where)
        bases[i] = basis * norms[i]
        frames[i] = basis if p.frame == "world" else np.column_stack([np.cross(basis[:, 1], basis[:, 2]), basis[:, 1:]])
        parent_long = longs[parents[i]] if parents[i] >= 0 else None
        for d in p.dofs:
            dof_parts.append(i)
            dof_axes.append(resolve_axis(d.axis, basis, longs[i], parent_long, f"{where}: dof {d.name!r}"))
            at_rest = d.rest
            if at_rest is None:
                at_rest = float(np.arccos(np.clip(parent_long @ longs[i], -1.0, 1.0)))
                if not d.lower <= at_rest <= d.upper:
                    raise HitogataError(
                        f"{where}: dof {d.name!r}: measured rest {np.degrees(at_rest):.1f}° is outside "
                        f"[{np.degrees(d.lower):g}, {np.degrees(d.upper):g}] degrees"
                    )
            lower.append(d.lower - at_rest)
            upper.append(d.upper - at_rest)
            rest.append(at_rest)
    return Skeleton(
        spec=spec,
        names=spec.names,
        parents=parents,
        joints=joints,
        tails=tails,
        frames=frames,
        bases=bases,
        dof_names=spec.dof_names,
        dof_parts=np.array(dof_parts, dtype=np.int64),
        dof_axes=np.array(dof_axes, dtype=float).reshape(-1, 3),
        lower=np.array(lower, dtype=float),
        upper=np.array(upper, dtype=float),
        rest=np.array(rest, dtype=float),
    )
