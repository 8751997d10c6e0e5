"""A region's angle shared among its segments: the thoracolumbar spine or the neck bent as a whole.

A person bends the trunk or turns the head with every vertebra taking a part;
the skeleton list gives each segment its own range, and a region's angle is
shared among them in proportion to those ranges on the side it turns to (the
way the ranges themselves were shared from the regional AAOS ranges).
"""

from __future__ import annotations

import math
from functools import cache

import numpy as np

from hitogata.errors import HitogataError
from hitogata.skeleton.combined import SPINE
from hitogata.skeleton.placement import Skeleton

# Region name → the parts whose DOFs it moves together.
STRETCHES: dict[str, tuple[str, ...]] = {
    "lumbar": tuple(p for p in SPINE if p.startswith("lumbar_")),
    "thoracic": tuple(p for p in SPINE if p.startswith("thoracic_")),
    "spine": SPINE,
    "neck": tuple(f"cervical_{i}" for i in range(1, 8)) + ("head",),
}


def stretch_dofs(skeleton: Skeleton, stretch: str, dof: str) -> tuple[str, ...]:
    """The DOF names of one motion (`flexion`, `lateral_bending`, `rotation`) along a region."""
    return _named(tuple(skeleton.dof_names), stretch, dof)


@cache
def _named(dof_names: tuple[str, ...], stretch: str, dof: str) -> tuple[str, ...]:
    parts = STRETCHES[stretch]
    return tuple(n for n in dof_names if n.partition(".")[0] in parts and n.endswith(f".{dof}"))


def spread(skeleton: Skeleton, stretch: str, dof: str, angle: float, where: str) -> dict[str, float]:
    """Rest-relative angles (radians) of the region's `dof` summing to `angle`, each in proportion to its range.

    One line naming `where` if the region has no such motion or cannot turn that far.
    """
    names = stretch_dofs(skeleton, stretch, dof)
    if not names:
        raise HitogataError(f"{where}: no {dof!r} along the {stretch}; allowed flexion, lateral_bending, rotation")
    index = [skeleton.dof_index(n) for n in names]
    reach = skeleton.upper[index] if angle >= 0 else -skeleton.lower[index]
    if abs(angle) > reach.sum() + 1e-9:
        raise HitogataError(f"{where} = {math.degrees(angle):.1f}°: the {stretch} allows "
                            f"{math.degrees(reach.sum()):.1f}° at most")
    share = angle * reach / max(float(reach.sum()), 1e-12)
    return {n: float(a) for n, a in zip(names, np.asarray(share))}
