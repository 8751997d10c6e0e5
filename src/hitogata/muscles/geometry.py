"""Muscles on a placed skeleton: the triangle of eq. 1 or the helix of eq. 2 at rest.

A muscle moves one degree of freedom of one or more joints. Its length is a
function of one angle Θ, the sum of those joints' angles ('range' or explicit
shares: serial joints, e.g. the vertebrae under the rectus abdominis) or their
mean ('same': parallel joints, e.g. four fingers under one flexor), measured
on an equivalent joint: the share-weighted mean of the joint centres and of the
DOF axes (a single joint is its own equivalent joint). Other DOFs stay at rest
in this measure, as in the paper, where each muscle makes one basic motion.

Flexion (eq. 1): origin d and insertion e are projected onto the plane through
the joint a normal to the axis u; d1 = |ad|, d2 = |ae|. With α0 the signed
angle from ad to ae about u at rest, the triangle's angle is θ = |α0 + Θ|, so
θ = θ0 + κΘ with θ0 = |α0| and κ = sign(α0), valid while 0 ≤ θ ≤ π.

Rotation (eq. 2): the muscle winds round the axis from origin to insertion,
over the height d between them along u, through the angle φ0 its handedness
gives (0…2π), on a cylinder of the given radius r; turning the distal part by
Θ about u changes the wrap to φ = φ0 + sΘ (s = ±1), valid while φ ≥ 0.

Either way, shortening the muscle turns Θ in the direction −κ (or −s): its
`sense`.
"""

from __future__ import annotations

import warnings

from dataclasses import dataclass

import numpy as np

from hitogata.errors import HitogataError
from hitogata.muscles.spec import MuscleListSpec, MuscleSpec
from hitogata.skeleton.placement import Skeleton

MAX_AXIS_SPREAD = np.cos(np.radians(45.0))  # serial joints of one muscle turn about similar axes
MIN_ARM = 1e-4  # m: attachments nearer the axis than this have no lever


@dataclass(frozen=True, eq=False)
class MuscleSet:
    """A muscle list placed on a skeleton: rest geometry and the joint-angle maps.

    `share_pos`/`share_neg` (M, D): the DOF angles a muscle angle Θ ≥ 0 / < 0
    sets (q = Θ · share); `gather` (M, D): Θ = gather @ q. `low`/`high`: Θ's
    range of motion from the joints' limits; `reach_low`/`reach_high`: where
    eq. 1 or eq. 2 stays defined.
    """

    spec: MuscleListSpec
    skeleton: Skeleton
    names: tuple[str, ...]
    rotation: np.ndarray  # (M,) bool
    rest_length: np.ndarray  # (M,) m
    d1: np.ndarray  # (M,) flexion
    d2: np.ndarray
    theta0: np.ndarray
    kappa: np.ndarray
    height: np.ndarray  # (M,) rotation
    radius: np.ndarray
    phi0: np.ndarray
    s: np.ndarray
    share_pos: np.ndarray
    share_neg: np.ndarray
    gather: np.ndarray
    low: np.ndarray
    high: np.ndarray
    reach_low: np.ndarray
    reach_high: np.ndarray
    centres: np.ndarray  # (M, 3) equivalent joint centres
    axes: np.ndarray  # (M, 3)
    origins: np.ndarray  # (M, 3) rest attachment points
    insertions: np.ndarray  # (M, 3)
    origin_parts: np.ndarray  # (M,) the parts carrying them
    insertion_parts: np.ndarray  # (M,)

    @property
    def sense(self) -> np.ndarray:
        """(M,) ±1: the direction in which contracting the muscle turns its joints."""
        return -np.where(self.rotation, self.s, self.kappa)

    def index(self, name: str) -> int:
        try:
            return self.names.index(name)
        except ValueError:
            raise HitogataError(f"{self.spec.source}: no muscle named {name!r}") from None

    def dofs(self, muscle: int) -> np.ndarray:
        """Indices of the DOFs a muscle moves."""
        return np.flatnonzero(self.gather[muscle])


class MuscleGeometryWarning(UserWarning):
    """A muscle's geometry on this body is less exact than the list assumes."""


def signed_angle(a: np.ndarray, b: np.ndarray, axis: np.ndarray) -> float:
    """Angle from a to b about a unit axis, in (−π, π]."""
    return float(np.arctan2(axis @ np.cross(a, b), a @ b))


def shares(
    m: MuscleSpec, lower: np.ndarray, upper: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(positive shares, negative shares, gather row, position weights) over the muscle's joints."""
    n = len(m.joints)
    if m.distribution == "same":
        one = np.ones(n)
        return one, one, one / n, np.eye(n)[0]
    if isinstance(m.distribution, tuple):
        w = np.array(m.distribution)
        return w, w, np.ones(n), w
    pos = upper / upper.sum() if upper.sum() > 0 else np.full(n, 1.0 / n)
    neg = lower / lower.sum() if lower.sum() < 0 else np.full(n, 1.0 / n)
    span = upper - lower
    return pos, neg, np.ones(n), span / span.sum()


def place_muscles(spec: MuscleListSpec, skeleton: Skeleton) -> MuscleSet:
    """Place a muscle list on a skeleton placed on a body."""
    if spec.skeleton is not skeleton.spec:
        raise HitogataError(f"{spec.source}: the muscle list was checked against another skeleton list")
    n_m, n_d = len(spec.muscles), skeleton.n_dofs
    out = {
        k: np.zeros(n_m)
        for k in (
            "rest_length",
            "d1",
            "d2",
            "theta0",
            "kappa",
            "height",
            "radius",
            "phi0",
            "s",
            "low",
            "high",
            "reach_low",
            "reach_high",
        )
    }
    share_pos, share_neg, gather = np.zeros((n_m, n_d)), np.zeros((n_m, n_d)), np.zeros((n_m, n_d))
    centres, axes, origins, insertions = (np.zeros((n_m, 3)) for _ in range(4))
    for k, m in enumerate(spec.muscles):
        where = f"{spec.source}: muscle {m.name!r}"
        dofs = np.array([skeleton.dof_index(f"{j}.{m.dof}") for j in m.joints])
        lo, hi = skeleton.lower[dofs], skeleton.upper[dofs]
        pos, neg, row, weights = shares(m, lo, hi)
        share_pos[k, dofs], share_neg[k, dofs], gather[k, dofs] = pos, neg, row
        if m.distribution == "same":
            out["low"][k], out["high"][k] = lo.max(), hi.min()
        elif isinstance(m.distribution, tuple):
            used = pos > 0
            out["low"][k], out["high"][k] = (lo[used] / pos[used]).max(), (hi[used] / pos[used]).min()
        else:
            out["low"][k], out["high"][k] = lo.sum(), hi.sum()

        parts = skeleton.dof_parts[dofs]
        a = weights @ skeleton.joints[parts]
        u = weights @ skeleton.dof_axes[dofs]
        u /= np.linalg.norm(u)
        spread = np.degrees(np.arccos(np.clip((skeleton.dof_axes[dofs] @ u).min(), -1.0, 1.0)))
        if m.distribution != "same" and spread > np.degrees(np.arccos(MAX_AXIS_SPREAD)):
            # Old and short heavy bodies lean the upper neck far forward, so the
            # vertebral frames fan out; the muscle then acts about the mean axis.
            warnings.warn(
                f"{where}: its joints' {m.dof!r} axes differ by {spread:.0f}° on this body; "
                "its triangle uses their mean axis",
                MuscleGeometryWarning,
                stacklevel=2,
            )
        o = skeleton.point(skeleton.index(m.origin.part), m.origin.at)
        e = skeleton.point(skeleton.index(m.insertion.part), m.insertion.at)
        centres[k], axes[k], origins[k], insertions[k] = a, u, o, e
        po, pe = (o - a) - ((o - a) @ u) * u, (e - a) - ((e - a) @ u) * u
        if min(np.linalg.norm(po), np.linalg.norm(pe)) < MIN_ARM:
            raise HitogataError(f"{where}: origin or insertion lies on the joint's axis; move it off the axis")
        if m.kind == "flexion":
            alpha = signed_angle(po, pe, u)
            if abs(alpha) < 1e-6 or abs(abs(alpha) - np.pi) < 1e-6:
                raise HitogataError(
                    f"{where}: origin and insertion are in line with the joint; the muscle has no lever"
                )
            d1, d2, kappa = np.linalg.norm(po), np.linalg.norm(pe), np.sign(alpha)
            out["d1"][k], out["d2"][k], out["theta0"][k], out["kappa"][k] = d1, d2, abs(alpha), kappa
            out["rest_length"][k] = np.linalg.norm(po - pe)
            edges = np.array([-abs(alpha), np.pi - abs(alpha)]) * kappa
        else:
            rise = (e - a) @ u - (o - a) @ u
            if abs(rise) < MIN_ARM:
                raise HitogataError(
                    f"{where}: origin and insertion are level along the axis; the helix has no handedness"
                )
            turn = signed_angle(po, pe, u) * np.sign(rise) * m.handedness
            phi0, s = turn % (2 * np.pi), m.handedness * np.sign(rise)
            out["height"][k], out["radius"][k], out["phi0"][k], out["s"][k] = abs(rise), m.radius, phi0, s
            out["rest_length"][k] = np.hypot(abs(rise), m.radius * phi0)
            edges = np.array([-phi0 * s, np.inf * s])
        out["reach_low"][k], out["reach_high"][k] = edges.min(), edges.max()
    return MuscleSet(
        spec=spec,
        skeleton=skeleton,
        names=spec.names,
        rotation=np.array([m.kind == "rotation" for m in spec.muscles]),
        share_pos=share_pos,
        share_neg=share_neg,
        gather=gather,
        centres=centres,
        axes=axes,
        origins=origins,
        insertions=insertions,
        origin_parts=np.array([skeleton.index(m.origin.part) for m in spec.muscles], dtype=np.int64),
        insertion_parts=np.array([skeleton.index(m.insertion.part) for m in spec.muscles], dtype=np.int64),
        **out,
    )
