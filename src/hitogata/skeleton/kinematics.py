"""Forward kinematics: joint angles → the world transform of every part, batched.

Each part's joint rotates it about its DOF axes (fixed in the part, applied in
list order, i.e. intrinsic) round its joint centre. Its skinning transform
maps rest positions to posed ones: M_i = M_parent · T(J_i) · L_i · T(−J_i),
so every part stays rigid and every joint centre stays on its parent: bone
lengths are kept to rounding. Parts of one tree depth are composed together,
so the cost is numpy work on (P, parts-at-depth) arrays, not a loop over poses.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from hitogata.errors import HitogataError
from hitogata.options import LIMIT_MODES, Limits
from hitogata.skeleton.placement import Skeleton
from hitogata.geometry.rotations import axis_rotations

# Limits are shown to 0.1°: an angle within half that digit of a limit is on it (a value read
# back from a message, a file or another unit is accepted, not refused as outside itself).
LIMIT_TOLERANCE = np.radians(0.05)


@dataclass(frozen=True, eq=False)
class Pose:
    """P posed skeletons: skinning transforms x ↦ R x + t, rest world → posed world."""

    skeleton: Skeleton
    rotations: np.ndarray  # (P, N, 3, 3)
    translations: np.ndarray  # (P, N, 3)

    @property
    def matrices(self) -> np.ndarray:
        """(P, N, 4, 4) homogeneous skinning transforms."""
        p, n = self.rotations.shape[:2]
        m = np.zeros((p, n, 4, 4))
        m[..., :3, :3] = self.rotations
        m[..., :3, 3] = self.translations
        m[..., 3, 3] = 1.0
        return m

    @cached_property
    def joints(self) -> np.ndarray:
        """(P, N, 3) posed joint centres."""
        return np.einsum("pnij,nj->pni", self.rotations, self.skeleton.joints) + self.translations

    @cached_property
    def tails(self) -> np.ndarray:
        """(P, N, 3) posed tails."""
        return np.einsum("pnij,nj->pni", self.rotations, self.skeleton.tails) + self.translations

    @property
    def frames(self) -> np.ndarray:
        """(P, N, 3, 3) posed part orientations (columns: the part's x, y, z)."""
        return self.rotations @ self.skeleton.frames


class Kinematics:
    """Precomputed index plan for one skeleton; call `pose` as often as needed."""

    def __init__(self, skeleton: Skeleton):
        self.skeleton = skeleton
        n = len(skeleton.names)
        jump = np.where(skeleton.parents < 0, n, skeleton.parents)  # n: an identity sentinel
        jump = np.append(jump, n)
        self.jumps = []
        while np.any(jump[:n] < n):
            self.jumps.append(jump)
            jump = jump[jump]
        slot = np.zeros(skeleton.n_dofs, dtype=np.int64)
        for k in range(1, skeleton.n_dofs):
            same = skeleton.dof_parts[k] == skeleton.dof_parts[k - 1]
            slot[k] = slot[k - 1] + 1 if same else 0
        self.slots = [np.flatnonzero(slot == s) for s in range(int(slot.max(initial=-1)) + 1)]

    def check_limits(self, angles: np.ndarray, mode: Limits) -> np.ndarray:
        """Angles within limits: unchanged ('ignore'), clamped ('clamp') or an error ('raise')."""
        sk = self.skeleton
        if mode not in LIMIT_MODES:
            raise HitogataError(f"limits = {mode!r}: allowed {', '.join(LIMIT_MODES)}")
        if mode == "clamp":
            return np.clip(angles, sk.lower, sk.upper)
        if mode == "raise":
            bad = limit_violations(sk, angles)
            if bad.any():
                k = int(np.flatnonzero(bad.reshape(-1, sk.n_dofs).any(axis=0))[0])
                value = angles.reshape(-1, sk.n_dofs)[:, k]
                worst = value[np.argmax(np.maximum(sk.lower[k] - value, value - sk.upper[k]))]
                raise HitogataError(
                    f"{sk.dof_names[k]} = {np.degrees(sk.rest[k] + worst):.1f}° clinical: "
                    f"allowed {np.degrees(sk.rest[k] + sk.lower[k]):.1f}…{np.degrees(sk.rest[k] + sk.upper[k]):.1f}°"
                )
        return angles

    def local_transforms(self, angles: np.ndarray) -> np.ndarray:
        """(P, N+1, 4, 4) joint transforms T(J) L T(−J), DOFs composed in list order; last = identity."""
        sk = self.skeleton
        n_pose, n = len(angles), len(sk.names)
        local = np.zeros((n_pose, n + 1, 4, 4))
        rot = local[:, :n, :3, :3]
        rot[:] = np.eye(3)
        for dofs in self.slots:
            parts = sk.dof_parts[dofs]
            rot[:, parts] = rot[:, parts] @ axis_rotations(sk.dof_axes[dofs], angles[:, dofs])
        local[:, :n, :3, 3] = sk.joints - (rot @ sk.joints[:, :, None])[..., 0]
        local[:, :, 3, 3] = 1.0
        local[:, n, :3, :3] = np.eye(3)
        return local

    def pose(self, angles: np.ndarray, root: np.ndarray | None = None, limits: Limits = "ignore") -> Pose:
        """Skinning transforms for angles (D,) or (P, D), rest-relative radians.

        `root` is an optional (4, 4) or (P, 4, 4) transform of the whole body.
        """
        sk = self.skeleton
        a = np.asarray(angles, dtype=float)
        if a.shape[-1:] != (sk.n_dofs,) or a.ndim not in (1, 2):
            raise HitogataError(f"angles of shape {a.shape}: allowed ({sk.n_dofs},) or (P, {sk.n_dofs})")
        a = self.check_limits(np.atleast_2d(a), limits)
        m = self.local_transforms(a)
        if root is not None:
            m[:, 0] = np.asarray(root, dtype=float) @ m[:, 0]
        for jump in self.jumps:
            m = m[:, jump] @ m
        n = len(sk.names)
        return Pose(sk, m[:, :n, :3, :3], m[:, :n, :3, 3])


def limit_violations(skeleton: Skeleton, angles: np.ndarray) -> np.ndarray:
    """Boolean mask, same shape as angles: outside the DOF's range of motion (beyond `LIMIT_TOLERANCE`)."""
    a = np.asarray(angles, dtype=float)
    return (a < skeleton.lower - LIMIT_TOLERANCE) | (a > skeleton.upper + LIMIT_TOLERANCE)


def forward_kinematics(
    skeleton: Skeleton, angles: np.ndarray, root: np.ndarray | None = None, limits: Limits = "ignore"
) -> Pose:
    """Pose a skeleton: joint angles (D,) or (P, D) → world transforms of all parts.

    limits: 'ignore' (poses as given), 'clamp' (into the ranges of motion)
    or 'raise' (a one-line error naming the first DOF out of range);
    `limit_violations` reports them without acting.
    """
    return Kinematics(skeleton).pose(angles, root=root, limits=limits)
