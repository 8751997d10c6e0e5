"""The muscles as a list: load and check the TOML file that defines them.

One `[[muscle]]` entry per muscle (`data/muscles.toml` by default): its kind
(`flexion`, eq. 1, or `rotation`, eq. 2), the joints and the degree of freedom
it moves, its origin and insertion (a part and a point in that part's frame,
in units of the part's length), its antagonist, and for rotation muscles the
radius of the cylinder it winds round (metres) and its handedness. A muscle
moving several joints says how its angle is shared among them
(`distribution`). Checked against a skeleton list; every mistake is a
one-line `HitogataError` naming the file and the muscle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

from hitogata.errors import HitogataError
from hitogata.config import Entry, read_toml
from hitogata.options import DISTRIBUTIONS, MUSCLE_KINDS as KINDS
from hitogata.skeleton.spec import SkeletonSpec

DEFAULT_FILE = "muscles.toml"
HANDEDNESS = {"right": 1, "left": -1}


@dataclass(frozen=True)
class Attachment:
    """A point fixed in a part: coordinates in the part's frame, in part lengths."""

    part: str
    at: tuple[float, float, float]


@dataclass(frozen=True)
class MuscleSpec:
    """One muscle. `distribution`: 'range' (serial joints share the angle in
    proportion to their ranges of motion), 'same' (parallel joints, e.g. the
    four fingers, each turn by the whole angle) or explicit serial shares."""

    name: str
    kind: str
    joints: tuple[str, ...]
    dof: str
    origin: Attachment
    insertion: Attachment
    antagonist: str
    distribution: str | tuple[float, ...]
    radius: float | None  # m, rotation only
    handedness: int  # +1 right, -1 left, 0 for flexion


@dataclass(frozen=True)
class MuscleListSpec:
    """A checked muscle list for a skeleton list."""

    source: str
    skeleton: SkeletonSpec
    muscles: tuple[MuscleSpec, ...]

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(m.name for m in self.muscles)


def default_muscles_path() -> Path:
    """The muscle list shipped with the package."""
    return Path(str(resources.files("hitogata").joinpath("data", DEFAULT_FILE)))


def parse_attachment(entry: Entry, key: str, parts: set[str]) -> Attachment:
    sub = Entry(entry.source, f"{entry.where}: {key}", entry.get(key, dict), ("part", "at"))
    part = sub.get("part", str)
    if part not in parts:
        sub.fail(f"unknown part {part!r}")
    at = sub.get("at", list)
    if len(at) != 3 or not all(
        isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in at
    ):
        sub.fail(f"at = {at!r}: expected three numbers (part lengths)")
    x, y, z = (float(v) for v in at)
    return Attachment(part, (x, y, z))


def subtree(skeleton: SkeletonSpec, part: str) -> set[str]:
    """A part and every part below it."""
    below, changed = {part}, True
    while changed:
        grown = below | {p.name for p in skeleton.parts if p.parent in below}
        changed, below = len(grown) > len(below), grown
    return below


def parse_muscle(source: str, index: int, value: Any, skeleton: SkeletonSpec) -> MuscleSpec:
    keys = (
        "name",
        "kind",
        "joints",
        "dof",
        "origin",
        "insertion",
        "antagonist",
        "distribution",
        "radius",
        "handedness",
    )
    entry = Entry(source, f"muscle {index}", value, keys)
    name = entry.get("name", str)
    entry.where = f"muscle {name!r}"
    kind = entry.get("kind", str)
    if kind not in KINDS:
        entry.fail(f"unknown kind {kind!r}; allowed: {', '.join(KINDS)}")
    parts = {p.name: p for p in skeleton.parts}
    joints = entry.names("joints")
    if not joints or len(set(joints)) != len(joints):
        entry.fail(f"joints = {list(joints)}: expected one or more distinct parts")
    dof = entry.get("dof", str)
    for j in joints:
        if j not in parts:
            entry.fail(f"unknown part {j!r} in joints")
        if dof not in [d.name for d in parts[j].dofs]:
            entry.fail(f"part {j!r} has no degree of freedom {dof!r}")
    origin = parse_attachment(entry, "origin", set(parts))
    insertion = parse_attachment(entry, "insertion", set(parts))

    distribution: str | tuple[float, ...] = "range"
    if entry.has("distribution"):
        raw = entry.get("distribution", (str, list))
        if isinstance(raw, str):
            if raw not in DISTRIBUTIONS:
                entry.fail(f"distribution = {raw!r}; allowed: {', '.join(DISTRIBUTIONS)} or a list of shares")
            distribution = raw
        else:
            ok = len(raw) == len(joints) and all(isinstance(v, (int, float)) and v >= 0 for v in raw)
            if not ok or abs(sum(raw) - 1.0) > 1e-9:
                entry.fail(f"distribution = {raw!r}: expected {len(joints)} shares >= 0 summing to 1")
            distribution = tuple(float(v) for v in raw)

    moved = joints[:1] if distribution == "same" else joints
    for j in moved:
        below = subtree(skeleton, j)
        if origin.part in below:
            entry.fail(f"origin part {origin.part!r} is moved by joint {j!r}; it must be on the proximal side")
        if insertion.part not in below:
            entry.fail(f"insertion part {insertion.part!r} is not moved by joint {j!r}")

    radius, handedness = None, 0
    if kind == "rotation":
        radius = entry.number("radius")
        if radius <= 0:
            entry.fail(f"radius = {radius:g} m: expected > 0")
        hand = entry.get("handedness", str)
        if hand not in HANDEDNESS:
            entry.fail(f"handedness = {hand!r}; allowed: right, left")
        handedness = HANDEDNESS[hand]
    elif entry.has("radius") or entry.has("handedness"):
        entry.fail("radius and handedness apply to rotation muscles only")
    return MuscleSpec(
        name, kind, joints, dof, origin, insertion, entry.get("antagonist", str), distribution, radius, handedness
    )


def load_muscle_spec(skeleton: SkeletonSpec, path: str | Path | None = None) -> MuscleListSpec:
    """Read and check a muscle list (the shipped one when `path` is None)."""
    source, doc = read_toml(default_muscles_path() if path is None else path)
    top = Entry(source, "top level", doc, ("muscle",))
    raw = top.get("muscle", list)
    if not raw:
        top.fail("no [[muscle]] entries")
    muscles = [parse_muscle(source, k, v, skeleton) for k, v in enumerate(raw)]
    by_name: dict[str, MuscleSpec] = {}
    for m in muscles:
        if m.name in by_name:
            raise HitogataError(f"{source}: muscle {m.name!r}: duplicate name")
        by_name[m.name] = m
    for m in muscles:
        other = by_name.get(m.antagonist)
        if other is None or other is m:
            raise HitogataError(
                f"{source}: muscle {m.name!r}: antagonist {m.antagonist!r} is not another muscle in the list"
            )
        if (other.joints, other.dof) != (m.joints, m.dof):
            raise HitogataError(
                f"{source}: muscle {m.name!r}: antagonist {other.name!r} moves {other.dof} of {list(other.joints)}, "
                f"not {m.dof} of {list(m.joints)}"
            )
    return MuscleListSpec(source, skeleton, tuple(muscles))
