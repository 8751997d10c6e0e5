"""Limits that only make sense together: the shoulder complex, the thoracolumbar spine, the two hips.

A joint's own range (the skeleton list) is measured with the neighbouring
joints free; some motions are bounded by what several joints do together:
- the arm's abduction is glenohumeral + scapular + clavicular (AAOS 180°:
  together they cannot carry the arm past the vertical into the head);
- the thoracolumbar spine bends as a whole (AAOS regional ranges: flexion
  80°, extension 25°, lateral bending 35°, rotation 45°; the shipped
  segments' ranges are shared from these, so this guards edited lists);
- a hip adducts 30° (AAOS) with the other leg out of the way: with both legs
  straight they meet, so the two hips' adductions (abduction below zero)
  together stay within 30°.
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
HIP_ADDUCTION_TOGETHER = 30.0


@dataclass(frozen=True)
class CombinedLimit:
    """A sum of clinical angles (radians) that must stay within [lower, upper]."""

    name: str
    dofs: tuple[str, ...]
    lower: float
    upper: float


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
                      -rad(HIP_ADDUCTION_TOGETHER), math.inf)
    )
    names = set(skeleton.dof_names)
    return tuple(c for c in limits if set(c.dofs) <= names)


def combined_violation(skeleton: Skeleton, angles: np.ndarray, skip: frozenset[str] = frozenset()) -> str | None:
    """A one-line description of the first combined limit rest-relative `angles` (D,) break, or None;
    limits named in `skip` are not checked (a shoulder set by its complex control has its own range)."""
    clinical = skeleton.clinical(angles)
    for c in combined_limits(skeleton):
        if c.name in skip:
            continue
        total = float(sum(clinical[skeleton.dof_index(n)] for n in c.dofs))
        slack = LIMIT_TOLERANCE * len(c.dofs)  # each addend's range is given to 0.1°
        if c.lower - slack <= total <= c.upper + slack:
            continue
        what = " + ".join(c.dofs) if len(c.dofs) <= 3 else f"{c.dofs[0]} + … + {c.dofs[-1]}"
        if math.isinf(c.upper):
            allowed = f"at least {math.degrees(c.lower):.1f}°"
        elif math.isinf(c.lower):
            allowed = f"at most {math.degrees(c.upper):.1f}°"
        else:
            allowed = f"{math.degrees(c.lower):.1f}…{math.degrees(c.upper):.1f}°"
        return f"{c.name} = {math.degrees(total):.1f}° clinical ({what}): the joints together allow {allowed}"
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
        total = float(clinical[idx].sum())
        excess = total - c.upper if total > c.upper else total - c.lower if total < c.lower else 0.0
        for _ in range(len(idx)):  # a DOF stopped by its own range passes its share on
            if abs(excess) <= 1e-12:
                break
            moved = np.clip(q[idx] - excess / len(idx), skeleton.lower[idx], skeleton.upper[idx])
            excess -= float((q[idx] - moved).sum())
            q[idx] = moved
        clinical = skeleton.clinical(q)
    return q
