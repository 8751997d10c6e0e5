"""Pose a body by its muscles or its joint angles: the library calls a CLI or viewer uses.

`Poser.from_body` places the skeleton and muscle lists on a body and prepares
its skin once; `Poser.pose` then goes muscles → joint angles (eq. 1, 2) →
forward kinematics → skinned surface, and `Poser.pose_many` does the last two
for a batch of joint-angle sets. `pose_body` is the one-call form.
Angles are in radians: `angles` relative to the rest pose, `clinical` from
the anatomical position (the TOML's convention); names are 'part.dof'.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cache, cached_property
from pathlib import Path

import numpy as np

from hitogata.body.model import Body
from hitogata.body.rig import carried_heads, carrying_parts
from hitogata.errors import HitogataError, excerpt
from hitogata.muscles.activation import (
    MuscleLimitWarning,
    angles_from_muscles,
    muscle_lengths,
)
from hitogata.muscles.geometry import MuscleSet, place_muscles
from hitogata.muscles.spec import MuscleListSpec, load_muscle_spec
from hitogata.options import ON_LIMIT, OnLimit, Skinning
from hitogata.posing.names import dof_candidates, suggestion
from hitogata.posing.skinning import Skin, prepare_skin, skin_vertices
from hitogata.skeleton.child_ranges import with_age_ranges
from hitogata.skeleton.combined import clamp_combined, combined_violation
from hitogata.skeleton.kinematics import LIMIT_TOLERANCE, Kinematics, Pose, limit_violations
from hitogata.skeleton.placement import Skeleton, place_skeleton
from hitogata.skeleton.shoulder import CHANNEL_RANGES, SIDES, channel_names, girdle_dofs, shoulder_pose
from hitogata.skeleton.spec import SkeletonSpec, load_skeleton_spec
from hitogata.skeleton.weights import part_weights


@cache
def shipped_lists() -> tuple[SkeletonSpec, MuscleListSpec]:
    """The shipped skeleton and muscle lists, read and checked once per process (they are frozen)."""
    spec = load_skeleton_spec()
    return spec, load_muscle_spec(spec)


@dataclass(frozen=True, eq=False)
class PosedBody:
    """One posed body: joint angles, part transforms, muscle lengths, the skinned surface and
    the rig's joint centres in the posture (what `hitogata.measure.measure(posed)` needs)."""

    body: Body
    skeleton: Skeleton
    muscles: MuscleSet
    angles: np.ndarray  # (D,) rest-relative, radians
    pose: Pose  # P = 1
    vertices: np.ndarray  # (V, 3)
    faces: np.ndarray  # (F, 3)
    muscle_lengths: np.ndarray  # (M,) metres
    rig_joints: np.ndarray  # (B, 3) the MakeHuman rig's joint centres (body.rig.names order) carried by the parts

    @property
    def muscle_names(self) -> tuple[str, ...]:
        """The muscles' names, in the order of `muscle_lengths`."""
        return self.muscles.names

    @property
    def joints(self) -> np.ndarray:
        """(N, 3) posed joint centres."""
        return self.pose.joints[0]

    @property
    def bones(self) -> np.ndarray:
        """(N, 2, 3) each part as a segment from its joint centre to its tail: the skeleton to draw."""
        return np.stack([self.pose.joints[0], self.pose.tails[0]], axis=1)

    @property
    def muscle_lines(self) -> np.ndarray:
        """(M, 2, 3) each muscle from its origin to its insertion, carried by their parts."""
        ends = []
        for points, parts in (
            (self.muscles.origins, self.muscles.origin_parts),
            (self.muscles.insertions, self.muscles.insertion_parts),
        ):
            r, t = self.pose.rotations[0, parts], self.pose.translations[0, parts]
            ends.append(np.einsum("mij,mj->mi", r, points) + t)
        return np.stack(ends, axis=1)

    @property
    def clinical(self) -> np.ndarray:
        """(D,) clinical joint angles, radians."""
        return self.skeleton.clinical(self.angles)

    def angle(self, name: str) -> float:
        """One DOF's rest-relative angle, radians."""
        return float(self.angles[self.skeleton.dof_index(name)])


@dataclass(frozen=True, eq=False)
class Poser:
    """A body with its skeleton, muscles and skin prepared for posing."""

    body: Body
    skeleton: Skeleton
    muscles: MuscleSet
    kinematics: Kinematics
    skin: Skin

    @cached_property
    def rig_parts(self) -> np.ndarray:
        """(B,) the part that carries each rig joint centre (`hitogata.body.rig.carrying_parts`)."""
        return carrying_parts(self.body.rig.heads, self.skeleton.joints)

    def rig_joints(self, rotations: np.ndarray, translations: np.ndarray) -> np.ndarray:
        """(..., B, 3) the rig's joint centres for part rotations (..., N, 3, 3) and translations (..., N, 3)."""
        return carried_heads(self.body.rig.heads, self.rig_parts, rotations, translations)

    @classmethod
    def from_body(cls, body: Body, skeleton: str | Path | None = None, muscles: str | Path | None = None) -> Poser:
        """Prepare a body; `skeleton`/`muscles` are TOML paths (the shipped lists when None)."""
        if skeleton is None and muscles is None:
            spec, muscle_spec = shipped_lists()
        else:
            spec = load_skeleton_spec(skeleton)
            muscle_spec = load_muscle_spec(spec, muscles)
        sk = with_age_ranges(place_skeleton(spec, body.rig), body.params.sex, body.params.age)
        ms = place_muscles(muscle_spec, sk)
        weights = part_weights(sk, body.rig, body.skin_weights, body.vertices)
        return cls(body, sk, ms, Kinematics(sk), prepare_skin(body.vertices, weights, sk.parents))

    def angles(
        self,
        contractions: Mapping[str, float] | None = None,
        lengths: Mapping[str, float] | None = None,
        angles: Mapping[str, float] | np.ndarray | None = None,
        clinical: Mapping[str, float] | None = None,
        on_limit: OnLimit = "raise",
    ) -> np.ndarray:
        """(D,) rest-relative joint angles from muscles and/or angles.

        A DOF named in `angles`/`clinical` may not also be moved by a given muscle;
        an angle array (D,) is a base pose on which the muscles set their DOFs.
        `clinical` also takes the shoulder complex ('shoulder_l.flexion', '.abduction':
        the girdle follows by the scapulohumeral rhythm, `hitogata.skeleton.shoulder`).
        Single joints are checked against their ranges, then the combined limits
        (`hitogata.skeleton.combined`).
        """
        if on_limit not in ON_LIMIT:
            raise HitogataError(f"on_limit = {on_limit!r}: allowed {', '.join(ON_LIMIT)}")
        for what, values, unit in (("contractions", contractions, "a fraction of the rest length"),
                                   ("lengths", lengths, "metres"), ("angles", angles, "radians"),
                                   ("clinical", clinical, "radians")):
            checked_numbers(what, values, unit, self.skeleton.dof_names if what in ("angles", "clinical") else None)
        sk, ms = self.skeleton, self.muscles
        complex_given = {k: v for k, v in (clinical or {}).items() if k in channel_names(sk)}
        single = {k: v for k, v in (clinical or {}).items() if k not in complex_given}
        base, given = self._given_angles(angles, single)
        base = self._limited(base, on_limit)
        base, set_by_complex = self._shoulders(base, given, complex_given, on_limit)
        given |= set_by_complex
        for name in list(contractions or {}) + list(lengths or {}):
            clash = [sk.dof_names[d] for d in ms.dofs(ms.index(name)) if d in given]
            if clash:
                raise HitogataError(f"{clash[0]} is set both by an angle and by muscle {name!r}: give one")
        q = angles_from_muscles(ms, contractions, lengths, base, on_limit)
        own_range = frozenset(f"{name.split('.')[0]}.abduction" for name in complex_given)
        return self._combined(q, on_limit, own_range)

    def _shoulders(
        self, q: np.ndarray, given: set[int], channels: Mapping[str, float], on_limit: str
    ) -> tuple[np.ndarray, set[int]]:
        """The shoulder-complex controls applied on `q`: girdle by the rhythm, glenohumeral solved."""
        sk, done = self.skeleton, set()
        for side in SIDES:
            prefix = f"shoulder_{side}."
            mine = {name[len(prefix):]: value for name, value in channels.items() if name.startswith(prefix)}
            if not mine:
                continue
            for motion, value in mine.items():
                lo, hi = np.radians(CHANNEL_RANGES[motion])
                if not np.isfinite(value):
                    raise HitogataError(f"shoulder_{side}.{motion} = {value!r}: expected a finite angle in radians")
                if lo - LIMIT_TOLERANCE <= value <= hi + LIMIT_TOLERANCE:
                    continue
                message = (
                    f"shoulder_{side}.{motion} = {np.degrees(value):.1f}° clinical: the shoulder complex "
                    f"allows {np.degrees(lo):.1f}…{np.degrees(hi):.1f}°"
                )
                if on_limit == "raise":
                    raise HitogataError(message)
                warnings.warn(f"clamped onto the range of motion: {message}", MuscleLimitWarning, stacklevel=4)
                mine[motion] = float(np.clip(value, lo, hi))
            flexion, abduction = mine.get("flexion", 0.0), mine.get("abduction", 0.0)
            if abs(flexion) > np.pi / 2 and abs(abduction) > np.pi / 2:
                elevation = np.degrees(np.arccos(np.clip(np.cos(flexion) * np.cos(abduction), -1.0, 1.0)))
                raise HitogataError(
                    f"shoulder_{side}.flexion {np.degrees(flexion):.0f}° with shoulder_{side}.abduction "
                    f"{np.degrees(abduction):.0f}°: the two turns past 90° undo each other (the arm ends "
                    f"{elevation:.0f}° from hanging); allowed at most one of them beyond 90° (the arm overhead: "
                    "flexion 180° or abduction 180° alone)")
            dofs = set(girdle_dofs(sk, side))
            if dofs & given:
                clash = sk.dof_names[min(dofs & given)]
                raise HitogataError(f"{clash} is set both by shoulder_{side} and on its own: give one")
            q = shoulder_pose(self.kinematics, q, side, mine.get("flexion", 0.0), mine.get("abduction", 0.0))
            done |= dofs
        return q, done

    def _given_angles(self, angles, clinical) -> tuple[np.ndarray, set[int]]:
        sk = self.skeleton
        q = np.zeros(sk.n_dofs)
        given: set[int] = set()
        if isinstance(angles, np.ndarray) or (angles is not None and not isinstance(angles, Mapping)):
            a = np.asarray(angles, dtype=float)
            if a.shape != (sk.n_dofs,):
                raise HitogataError(
                    f"angles of shape {a.shape}: expected ({sk.n_dofs},) or a mapping 'part.dof' -> radians"
                )
            return a.copy(), set()
        for values, offset in ((angles or {}, False), (clinical or {}, True)):
            for name, value in values.items():
                k = sk.dof_index(name)
                if k in given:
                    raise HitogataError(f"{name} given twice (as angle and as clinical angle): give one")
                if not np.isfinite(value):
                    raise HitogataError(f"{name} = {value!r}: expected a finite angle in radians")
                q[k] = value - sk.rest[k] if offset else value
                given.add(k)
        return q, given

    def _limited(self, q: np.ndarray, on_limit: str) -> np.ndarray:
        """Each DOF within its range; one within `LIMIT_TOLERANCE` of a limit is put on it."""
        sk = self.skeleton
        bad = limit_violations(sk, q)
        if bad.any():
            if on_limit == "raise":
                self.kinematics.check_limits(q, "raise")
            names = [sk.dof_names[k] for k in np.flatnonzero(bad)]
            warnings.warn(f"clamped onto the range of motion: {', '.join(names)}", MuscleLimitWarning, stacklevel=3)
        return np.clip(q, sk.lower, sk.upper)

    def _combined(self, q: np.ndarray, on_limit: str, skip: frozenset[str]) -> np.ndarray:
        """The combined limits (but `skip`): an error, or (clamp) the excess taken off the joints in equal shares."""
        message = combined_violation(self.skeleton, q, skip)
        if message is None:
            return q
        if on_limit == "raise":
            raise HitogataError(message)
        warnings.warn(f"clamped onto the range of motion: {message}", MuscleLimitWarning, stacklevel=3)
        return clamp_combined(self.skeleton, q, skip)

    def pose(
        self,
        contractions: Mapping[str, float] | None = None,
        lengths: Mapping[str, float] | None = None,
        angles: Mapping[str, float] | np.ndarray | None = None,
        clinical: Mapping[str, float] | None = None,
        skinning: Skinning = "lbs",
        on_limit: OnLimit = "raise",
        root: np.ndarray | None = None,
    ) -> PosedBody:
        """Muscles and/or angles → joint angles → kinematics → skinned surface."""
        q = self.angles(contractions, lengths, angles, clinical, on_limit)
        pose = self.kinematics.pose(q, root=root)
        verts = skin_vertices(self.skin, pose.rotations, pose.translations, skinning)[0]
        with warnings.catch_warnings():
            # a shoulder complex may turn the glenohumeral angles past what the single-joint
            # muscle triangles span (flexion 130–170°): those lengths stop at their reach
            warnings.simplefilter("ignore", MuscleLimitWarning)
            complex_set = any(name in channel_names(self.skeleton) for name in clinical or {})
            lengths_now = muscle_lengths(self.muscles, q, "clamp" if complex_set else on_limit)[0]
        return PosedBody(
            body=self.body,
            skeleton=self.skeleton,
            muscles=self.muscles,
            angles=q,
            pose=pose,
            vertices=verts,
            faces=self.body.faces,
            muscle_lengths=lengths_now,
            rig_joints=self.rig_joints(pose.rotations[0], pose.translations[0]),
        )

    def pose_many(self, angles: np.ndarray, skinning: Skinning = "lbs", root: np.ndarray | None = None) -> np.ndarray:
        """(P, V, 3) skinned surfaces for (P, D) rest-relative joint angles."""
        pose = self.kinematics.pose(np.atleast_2d(angles), root=root)
        return skin_vertices(self.skin, pose.rotations, pose.translations, skinning)


def checked_numbers(what: str, values: object, unit: str, dofs: Sequence[str] | None) -> None:
    """A mapping name → finite number (SI), or one line naming the entry; for joint angles, a name
    the command line accepts (`knee_r.flexion`) points to the skeleton's (`shank_r.flexion`)."""
    if values is None or isinstance(values, np.ndarray) and what == "angles":
        return
    if not isinstance(values, Mapping):
        raise HitogataError(f"{what} {excerpt(type(values).__name__)}: allowed a mapping name → {unit}")
    for name, value in values.items():
        if not isinstance(value, (int, float, np.number)) or isinstance(value, bool) or not np.isfinite(value):
            shown = excerpt(value) if isinstance(value, str) else repr(value)[:40]
            raise HitogataError(f"{what}[{excerpt(name)}] = {shown}: allowed a finite number in {unit} "
                                "(the API takes SI; units like '60deg' are for the command line and scenario files)")
        if dofs is not None and name not in dofs and not name.startswith("shoulder_"):
            meant = dof_candidates(str(name), dofs)
            hint = f"did you mean {', '.join(meant)} (the skeleton's name)?" if meant else suggestion(str(name), dofs)
            raise HitogataError(f"{what}[{excerpt(name)}]: no joint angle of that name; {hint}")


def poser_for(body: Body) -> Poser:
    """The body's Poser with the shipped lists, prepared once per body and kept with it (`Body.prepared`);
    `Poser.from_body` builds a new one, e.g. from other skeleton or muscle lists."""
    if not isinstance(body, Body):
        raise HitogataError(f"body {excerpt(type(body).__name__)}: allowed a Body "
                            "(e.g. Body.from_measurements(sex='female'))")
    return body.prepared(Poser.from_body)


def pose_body(
    body: Body,
    contractions: Mapping[str, float] | None = None,
    lengths: Mapping[str, float] | None = None,
    angles: Mapping[str, float] | np.ndarray | None = None,
    clinical: Mapping[str, float] | None = None,
    skinning: Skinning = "lbs",
    on_limit: OnLimit = "raise",
    root: np.ndarray | None = None,
) -> PosedBody:
    """Pose a body with the shipped skeleton and muscles.

    contractions: muscle name → fraction of rest length (0.1 = 10 % shorter,
    negative = stretched); lengths: muscle name → metres; angles / clinical:
    'part.dof' → radians (rest-relative / from the anatomical position);
    skinning: 'lbs' or 'dqs'; on_limit: 'raise' or 'clamp' (with a warning)
    at the muscles' reach and the joints' ranges of motion.
    """
    return poser_for(body).pose(contractions, lengths, angles, clinical, skinning, on_limit, root)
