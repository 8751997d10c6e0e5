"""Muscle and joint names as a person writes them → the skeleton's and muscles' list names.

One place for the shorthands the command line and the scenario files accept:
a joint's common name (`knee_r.flexion` for `shank_r.flexion`), and no side
suffix for both sides. An unknown name is a one-line error with the closest
known names (difflib).
"""

from __future__ import annotations

import difflib
from collections.abc import Sequence

from hitogata.errors import HitogataError

JOINT_NAMES = {
    "shoulder": "upper_arm",
    "elbow": "forearm",
    "wrist": "hand",
    "hip": "thigh",
    "knee": "shank",
    "ankle": "foot",
}
SIDES = ("_l", "_r")


def suggestion(name: str, known: Sequence[str]) -> str:
    """'did you mean a, b?' (the closest known names), or a few examples."""
    close = difflib.get_close_matches(name, list(known), n=3, cutoff=0.5)
    return f"did you mean {', '.join(close)}?" if close else f"e.g. {', '.join(list(known)[:3])}"


def dof_candidates(name: str, known: Sequence[str]) -> list[str]:
    """The DOFs a 'part.dof' name stands for (common joint names and side-less names resolved); [] if none."""
    part, _, dof = name.rpartition(".")
    side = next((s for s in SIDES if part.endswith(s)), "")
    base = part[: len(part) - len(side)]
    if f"{base}_l.{dof}" not in known:  # 'shoulder_l.flexion' is the shoulder complex's own control
        base = JOINT_NAMES.get(base, base)
    part = base + side
    candidates = [f"{part}.{dof}"] if side else [f"{part}.{dof}"] + [f"{part}{s}.{dof}" for s in SIDES]
    return [c for c in candidates if c in known]


def resolve_dofs(name: str, known: Sequence[str], where: str) -> list[str]:
    """The DOFs `name` stands for, or a one-line error at `where` naming the closest ones."""
    found = dof_candidates(name, known)
    if not found:
        common = {part: alias for alias, part in JOINT_NAMES.items()}
        spellings = set(known)
        for n in known:
            part, _, dof = n.partition(".")
            side = next((s for s in SIDES if part.endswith(s)), "")
            base = part[: len(part) - len(side)]
            spellings |= {f"{base}.{dof}", *(f"{common[base]}{s}.{dof}" for s in {side, ""} if base in common)}
        raise HitogataError(f"{where}: no joint angle {name!r}; {suggestion(name, sorted(spellings))}")
    return found


def resolve_muscles(name: str, known: Sequence[str], where: str) -> list[str]:
    """The muscles `name` stands for (itself, or both sides'), or a one-line error with the closest names."""
    if name in known:
        return [name]
    sided = [name + s for s in SIDES if name + s in known]
    if not sided:
        everything = list(known) + sorted({n[:-2] for n in known if n.endswith(SIDES)})
        raise HitogataError(f"{where}: no muscle {name!r}; {suggestion(name, everything)}")
    return sided
