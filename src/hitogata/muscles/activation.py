"""Contraction → joint angles by eq. 1 and eq. 2, and joint angles → muscle lengths.

The user sets some muscles' contractions (a fraction of the rest length:
0.1 = 10 % shorter, negative = stretched) or lengths (metres); each sets the
angles of the DOFs it moves, and every other muscle's length — its
antagonist's first — follows from the angles (`muscle_lengths`). Two given
muscles may not move the same DOF: give one, the other follows.

At the edges — a length outside eq. 1's |d1 − d2| … d1 + d2 or below eq. 2's
height d, or an angle beyond the joint's range of motion — `on_limit="raise"`
gives a one-line error and `on_limit="clamp"` clamps onto the edge with a
`MuscleLimitWarning` naming the muscles; never NaN. Everything is batched over
poses: values (P, k) → angles (P, D).
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence

import numpy as np

from hitogata.errors import HitogataError
from hitogata.muscles.equations import flexion_angle, flexion_length, rotation_angle, rotation_length
from hitogata.muscles.geometry import MuscleSet

from hitogata.options import ON_LIMIT  # noqa: E402  (owned there)
MODES = ("contraction", "length")


class MuscleLimitWarning(UserWarning):
    """A muscle length or a joint angle was clamped onto the edge of its domain."""


def _check_on_limit(on_limit: str) -> None:
    if on_limit not in ON_LIMIT:
        raise HitogataError(f"on_limit = {on_limit!r}: allowed {', '.join(ON_LIMIT)}")


class Drive:
    """A chosen set of driving muscles, compiled once; `angles` maps their values to joint angles."""

    def __init__(self, muscles: MuscleSet, names: Sequence[str], mode: str = "contraction"):
        if mode not in MODES:
            raise HitogataError(f"mode = {mode!r}: allowed {', '.join(MODES)}")
        self.muscles, self.mode = muscles, mode
        self.names = tuple(names)
        self.idx = np.array([muscles.index(n) for n in self.names], dtype=np.int64)
        owner: dict[int, str] = {}
        for name, m in zip(self.names, self.idx):
            for d in muscles.dofs(m):
                if d in owner:
                    raise HitogataError(
                        f"muscles {owner[d]!r} and {name!r} both move {muscles.skeleton.dof_names[d]}: "
                        "give one; the other's length follows from the angle"
                    )
                owner[d] = name
        self.driven = np.array(sorted(owner), dtype=np.int64)
        rot = muscles.rotation[self.idx]
        self.flex, self.rot = self.idx[~rot], self.idx[rot]
        self.flex_cols, self.rot_cols = np.flatnonzero(~rot), np.flatnonzero(rot)

    def muscle_angles(self, values: np.ndarray, on_limit: str = "raise") -> np.ndarray:
        """(P, k) muscle angles Θ (rest-relative, in the DOF's sense) from contractions or lengths."""
        _check_on_limit(on_limit)
        ms, clamp = self.muscles, on_limit == "clamp"
        v = np.atleast_2d(np.asarray(values, dtype=float))
        if v.shape[-1] != len(self.idx):
            raise HitogataError(
                f"values of shape {np.shape(values)}: expected (..., {len(self.idx)}) for {len(self.idx)} muscles"
            )
        length = v if self.mode == "length" else ms.rest_length[self.idx] * (1.0 - v)
        theta = np.empty_like(length)
        f, r = self.flex, self.rot
        clamped = self._outside_domain(length)
        if clamped.any():
            if not clamp:
                self._raise_domain(v, clamped)
            warnings.warn(self._clamp_message("muscle length", clamped), MuscleLimitWarning, stacklevel=3)
        lf = length[:, self.flex_cols]
        theta[:, self.flex_cols] = (flexion_angle(ms.d1[f], ms.d2[f], lf, clamp=True) - ms.theta0[f]) * ms.kappa[f]
        lr = length[:, self.rot_cols]
        theta[:, self.rot_cols] = (rotation_angle(lr, ms.height[r], ms.radius[r], clamp=True) - ms.phi0[r]) * ms.s[r]
        low, high = ms.low[self.idx], ms.high[self.idx]
        beyond = (theta < low - 1e-12) | (theta > high + 1e-12)
        if beyond.any():
            if not clamp:
                self._raise_range(v, theta, beyond)
            warnings.warn(self._clamp_message("range of motion", beyond), MuscleLimitWarning, stacklevel=3)
        return np.clip(theta, low, high)

    def angles(self, values: np.ndarray, base: np.ndarray | None = None, on_limit: str = "raise") -> np.ndarray:
        """(P, D) joint angles: `base` (rest when None) with the driven DOFs set by the muscles."""
        ms = self.muscles
        theta = self.muscle_angles(values, on_limit)
        n_dof = ms.skeleton.n_dofs
        q = np.zeros((len(theta), n_dof)) if base is None else np.array(np.broadcast_to(base, (len(theta), n_dof)))
        q[:, self.driven] = 0.0
        sp, sn = ms.share_pos[self.idx], ms.share_neg[self.idx]
        q += np.maximum(theta, 0.0) @ sp + np.minimum(theta, 0.0) @ sn
        return q

    def _outside_domain(self, length: np.ndarray) -> np.ndarray:
        ms = self.muscles
        lo = np.where(ms.rotation, ms.height, np.abs(ms.d1 - ms.d2))[self.idx]
        hi = np.where(ms.rotation, np.inf, ms.d1 + ms.d2)[self.idx]
        slack = 1e-12 * np.maximum(np.where(np.isfinite(hi), hi, lo), 1.0)
        if not np.all(np.isfinite(length)):
            raise HitogataError("muscle contractions and lengths must be finite numbers")
        return (length < lo - slack) | (length > hi + slack)

    def _raise_domain(self, values: np.ndarray, bad: np.ndarray) -> None:
        ms = self.muscles
        p, c = np.argwhere(bad)[0]
        m = self.idx[c]
        lo = ms.height[m] if ms.rotation[m] else abs(ms.d1[m] - ms.d2[m])
        hi = np.inf if ms.rotation[m] else ms.d1[m] + ms.d2[m]
        l0 = ms.rest_length[m]
        eq = "eq. 2 needs l >= d" if ms.rotation[m] else "eq. 1 needs |d1 - d2| <= l <= d1 + d2"
        if self.mode == "length":
            allowed = f"lengths {lo:.6g}…{hi:.6g} m" if np.isfinite(hi) else f"lengths >= {lo:.6g} m"
        else:
            allowed = (
                f"contractions {1 - hi / l0:.6g}…{1 - lo / l0:.6g}"
                if np.isfinite(hi)
                else f"contractions <= {1 - lo / l0:.6g}"
            )
        raise HitogataError(
            f"muscle {ms.names[m]!r}: {self.mode} {values[p, c]:.6g} is beyond its reach ({eq}): allowed {allowed}"
        )

    def _raise_range(self, values: np.ndarray, theta: np.ndarray, bad: np.ndarray) -> None:
        ms = self.muscles
        p, c = np.argwhere(bad)[0]
        m = self.idx[c]
        raise HitogataError(
            f"muscle {ms.names[m]!r}: {self.mode} {values[p, c]:.6g} turns {self._dof_label(m)} by "
            f"{np.degrees(theta[p, c]):.1f}°, beyond its range of motion {np.degrees(ms.low[m]):.1f}…"
            f"{np.degrees(ms.high[m]):.1f}° from rest"
        )

    def _dof_label(self, m: int) -> str:
        names = [self.muscles.skeleton.dof_names[d] for d in self.muscles.dofs(m)]
        return names[0] if len(names) == 1 else f"{len(names)} joints' {names[0].split('.')[1]}"

    def _clamp_message(self, what: str, bad: np.ndarray) -> str:
        hit = [self.names[c] for c in np.flatnonzero(bad.any(axis=0))]
        return f"clamped onto the edge of the {what}: {', '.join(hit)}"


def angles_from_muscles(
    muscles: MuscleSet,
    contractions: Mapping[str, float] | None = None,
    lengths: Mapping[str, float] | None = None,
    base: np.ndarray | None = None,
    on_limit: str = "raise",
) -> np.ndarray:
    """(D,) joint angles from a contraction (fraction) or a length (m) per named muscle."""
    given_c, given_l = dict(contractions or {}), dict(lengths or {})
    both = set(given_c) & set(given_l)
    if both:
        raise HitogataError(f"muscle {sorted(both)[0]!r}: give a contraction or a length, not both")
    lengths_all = {n: muscles.rest_length[muscles.index(n)] * (1.0 - c) for n, c in given_c.items()}
    lengths_all.update(given_l)
    if not lengths_all:
        return np.zeros(muscles.skeleton.n_dofs) if base is None else np.array(base, dtype=float)
    if given_c and not given_l:
        drive = Drive(muscles, list(given_c), "contraction")
        return drive.angles(np.array(list(given_c.values())), base, on_limit)[0]
    drive = Drive(muscles, list(lengths_all), "length")
    return drive.angles(np.array(list(lengths_all.values())), base, on_limit)[0]


def muscle_angles_of(muscles: MuscleSet, angles: np.ndarray) -> np.ndarray:
    """(P, M) muscle angles Θ of joint angles (P, D): the sum (or mean) over its joints."""
    return np.atleast_2d(np.asarray(angles, dtype=float)) @ muscles.gather.T


def muscle_lengths(muscles: MuscleSet, angles: np.ndarray, on_limit: str = "raise") -> np.ndarray:
    """(P, M) lengths (m) of every muscle for joint angles (D,) or (P, D), by the inverse of eq. 1/2.

    An angle outside a muscle's reach (θ outside 0…π, φ < 0) raises, or clamps
    with a `MuscleLimitWarning`.
    """
    _check_on_limit(on_limit)
    ms = muscles
    theta = muscle_angles_of(ms, angles)
    bad = (theta < ms.reach_low - 1e-12) | (theta > ms.reach_high + 1e-12)
    if bad.any():
        p, m = np.argwhere(bad)[0]
        if on_limit == "raise":
            raise HitogataError(
                f"muscle {ms.names[m]!r}: the joint angle {np.degrees(theta[p, m]):.1f}° from rest is beyond "
                f"what it can span ({np.degrees(ms.reach_low[m]):.1f}…{np.degrees(ms.reach_high[m]):.1f}°)"
            )
        hit = [ms.names[k] for k in np.flatnonzero(bad.any(axis=0))]
        warnings.warn(
            f"clamped onto the edge of the muscles' reach: {', '.join(hit)}", MuscleLimitWarning, stacklevel=2
        )
        theta = np.clip(theta, ms.reach_low, ms.reach_high)
    flex = flexion_length(ms.d1, ms.d2, np.clip(ms.theta0 + ms.kappa * theta, 0.0, np.pi))
    rot = rotation_length(np.maximum(ms.phi0 + ms.s * theta, 0.0), ms.height, np.where(ms.rotation, ms.radius, 1.0))
    return np.where(ms.rotation, rot, flex)


def contractions_of(muscles: MuscleSet, angles: np.ndarray, on_limit: str = "raise") -> np.ndarray:
    """(P, M) contractions (fractions of rest length) of every muscle for joint angles."""
    return 1.0 - muscle_lengths(muscles, angles, on_limit) / muscles.rest_length
