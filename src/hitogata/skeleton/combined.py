"""Limits that only make sense together: the shoulder complex, the thoracolumbar spine, the two hips.

A joint's own range (the skeleton list) is measured with the neighbouring
joints free; some motions are bounded by what several joints do together:
- the arm's abduction is glenohumeral + scapular + clavicular (AAOS 180°:
  together they cannot carry the arm past the vertical into the head);
- the thoracolumbar spine bends as a whole (AAOS regional ranges: flexion
  80°, extension 25°, lateral bending 35°, rotation 45°; the shipped
  segments' ranges are shared from these, so this guards edited lists);
- the two legs do not pass through each other: a hip adducts its 30° (AAOS:
  Greene & Heckman 1994, The Clinical Measurement of Joint Motion)
  with the other leg out of the way, in AAOS's test position abducted as
  far, so the two hips' clinical abductions sum to at least 0° (in the
  anatomical position, 0° each, the straight legs stand together). Measured
  on the DQS skin (`self_intersections` between the legs beyond the rest
  body's, bone capsules hip→knee→ankle→toes of radii 14, 13, 12 mm), the
  straight legs' skins begin to cross at a sum of −2° (default female),
  −8° (default male), +2° and +8° (male 195 cm and female 150 cm at BMI
  35 and 33: their thighs press together, soft tissue the contact parts),
  their bones at −12° to −14° on all four. One leg flexed ahead of the
  other makes room: at hip flexions 30°, 60°, 90° apart the default bodies'
  skins first cross at −4…−8°, −10…−12°, −22° and the bones no longer meet
  (to 30° of adduction), so past 30° apart the bound falls ⅓° per degree
  (−10° at 60°, −20° at 90°: hip flexion with adduction, e.g. the FADIR
  test or crossed legs).
Each limit is a sum of clinical angles, checked to half the shown digit per
addend; a pose beyond it is a one-line error naming the joint, its DOFs and
the combined range.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hitogata.errors import HitogataError
from hitogata.skeleton.kinematics import LIMIT_TOLERANCE
from hitogata.skeleton.placement import Skeleton

SPINE = tuple(f"lumbar_{i}" for i in range(1, 6)) + tuple(f"thoracic_{i}" for i in range(1, 13))
# AAOS thoracolumbar ranges (degrees), the same the segments' ranges are shared from.
SPINE_RANGES = {"flexion": (-25.0, 80.0), "lateral_bending": (-35.0, 35.0), "rotation": (-45.0, 45.0)}
SHOULDER_ABDUCTION = 180.0  # at most: past it the arm goes into the head
HIP_ABDUCTION_TOGETHER = 0.0  # at least: the straight legs meet below it
HIP_FLEXION_APART = 30.0  # the hips' flexions this far apart before one leg passes in front of the other
HIP_ROOM_PER_DEGREE = 1.0 / 3.0  # of abduction, per degree of flexion apart beyond that


@dataclass(frozen=True)
class CombinedLimit:
    """A sum of clinical angles (radians) that must stay within [lower, upper]; with `apart`, the
    lower bound falls by `room` per radian that the two DOFs' clinical angles lie more than `free` apart."""

    name: str
    dofs: tuple[str, ...]
    lower: float
    upper: float
    apart: tuple[str, ...] = ()
    free: float = 0.0
    room: float = 0.0

    def lowest(self, skeleton: Skeleton, clinical: np.ndarray) -> float:
        """The lower bound (radians) at these clinical angles (D,)."""
        if not self.apart:
            return self.lower
        a, b = (float(clinical[skeleton.dof_index(n)]) for n in self.apart)
        return self.lower - self.room * max(0.0, abs(a - b) - self.free)

    def allowed(self, skeleton: Skeleton, clinical: np.ndarray) -> str:
        """The combined range in words, degrees."""
        lower = self.lowest(skeleton, clinical)
        if math.isinf(self.upper):
            allowed = f"at least {math.degrees(lower):.1f}°"
        elif math.isinf(lower):
            allowed = f"at most {math.degrees(self.upper):.1f}°"
        else:
            allowed = f"{math.degrees(lower):.1f}…{math.degrees(self.upper):.1f}°"
        if not self.apart:
            return allowed
        a, b = (float(clinical[skeleton.dof_index(n)]) for n in self.apart)
        return (f"{allowed} with {self.apart[0]} and {self.apart[1]} {math.degrees(abs(a - b)):.1f}° apart "
                f"({math.degrees(self.lower):.1f}° up to {math.degrees(self.free):.0f}° apart, "
                f"{self.room:.2f}° less per degree beyond)")


def combined_limits(skeleton: Skeleton) -> tuple[CombinedLimit, ...]:
    """The combined limits whose DOFs this skeleton has (a custom list may lack some)."""
    rad = math.radians
    limits = [
        CombinedLimit(
            f"shoulder_{s}.abduction",
            (f"clavicle_{s}.elevation", f"scapula_{s}.upward_rotation", f"upper_arm_{s}.abduction"),
            -math.inf,  # a depressed girdle with the arm hanging is no collision
            rad(SHOULDER_ABDUCTION),
        )
        for s in ("l", "r")
    ]
    limits += [
        CombinedLimit(f"spine (lumbar_1…thoracic_12).{dof}", tuple(f"{p}.{dof}" for p in SPINE), rad(lo), rad(hi))
        for dof, (lo, hi) in SPINE_RANGES.items()
    ]
    limits.append(
        CombinedLimit("hips.abduction (both legs)", ("thigh_l.abduction", "thigh_r.abduction"),
                      rad(HIP_ABDUCTION_TOGETHER), math.inf, ("thigh_l.flexion", "thigh_r.flexion"),
                      rad(HIP_FLEXION_APART), HIP_ROOM_PER_DEGREE)
    )
    names = set(skeleton.dof_names)
    return tuple(c for c in limits if set(c.dofs) | set(c.apart) <= names)


def combined_violation(skeleton: Skeleton, angles: np.ndarray, skip: frozenset[str] = frozenset()) -> str | None:
    """A one-line description of the first combined limit rest-relative `angles` (D,) break, or None;
    limits named in `skip` are not checked (a shoulder set by its complex control has its own range)."""
    clinical = skeleton.clinical(angles)
    for c in combined_limits(skeleton):
        if c.name in skip:
            continue
        total = float(sum(clinical[skeleton.dof_index(n)] for n in c.dofs))
        slack = LIMIT_TOLERANCE * len(c.dofs)  # each addend's range is given to 0.1°
        if c.lowest(skeleton, clinical) - slack <= total <= c.upper + slack:
            continue
        what = " + ".join(c.dofs) if len(c.dofs) <= 3 else f"{c.dofs[0]} + … + {c.dofs[-1]}"
        return (f"{c.name} = {math.degrees(total):.1f}° clinical ({what}): the joints together allow "
                f"{c.allowed(skeleton, clinical)}")
    return None


def check_combined(skeleton: Skeleton, angles: np.ndarray) -> None:
    """Raise a one-line HitogataError at the first combined limit broken."""
    message = combined_violation(skeleton, angles)
    if message is not None:
        raise HitogataError(message)


def clamp_combined(skeleton: Skeleton, angles: np.ndarray, skip: frozenset[str] = frozenset()) -> np.ndarray:
    """Angles moved onto every broken combined limit: the excess shared equally, each DOF within its range."""
    q = np.array(angles, dtype=float)
    clinical = skeleton.clinical(q)
    for c in combined_limits(skeleton):
        if c.name in skip:
            continue
        idx = np.array([skeleton.dof_index(n) for n in c.dofs])
        total, lower = float(clinical[idx].sum()), c.lowest(skeleton, clinical)  # `apart` DOFs stay as they are
        excess = total - c.upper if total > c.upper else total - lower if total < lower else 0.0
        for _ in range(len(idx)):  # a DOF stopped by its own range passes its share on
            if abs(excess) <= 1e-12:
                break
            moved = np.clip(q[idx] - excess / len(idx), skeleton.lower[idx], skeleton.upper[idx])
            excess -= float((q[idx] - moved).sum())
            q[idx] = moved
        clinical = skeleton.clinical(q)
    return q
