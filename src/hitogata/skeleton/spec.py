"""The skeleton as a list: load and check the TOML file that defines the parts.

The paper writes the skeleton's connections as lists so that a part or a joint
can be added or removed by editing the list (§2.1). Here the list is a TOML
file (`data/skeleton.toml` by default): one `[[part]]` entry per part, naming
its parent, where its joint centre sits on the MakeHuman rig, its joint's
degrees of freedom with clinical ranges (degrees, converted to radians here,
once), and the rig bones whose skinning weights it takes. Every mistake is a
one-line `HitogataError` naming the file and the entry.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

from hitogata.config import Entry, read_toml
from hitogata.errors import HitogataError
from hitogata.options import AXES, ENDS, FRAMES

DEFAULT_FILE = "skeleton.toml"


@dataclass(frozen=True)
class Anchor:
    """A point on the rig: a bone end (or the mean of several), a fraction along a
    chain of bones, or another part's joint centre."""

    kind: str  # "bone" | "between" | "part"
    names: tuple[str, ...]  # bones (bone, between) or one part (part)
    end: str = "head"  # for "bone": which end of the bones
    fraction: float = 0.0  # for "between": arc-length fraction from the first bone's head


@dataclass(frozen=True)
class DofSpec:
    """One degree of freedom of a joint; angles in radians, clinical convention
    (0 = anatomical position), `rest` = the clinical angle of the rest pose
    (None: measured on each body as the bend between the part and its parent,
    for hinge axes)."""

    name: str
    axis: str
    lower: float
    upper: float
    rest: float | None


@dataclass(frozen=True)
class PartSpec:
    """One part: its parent (None for the root), joint centre, tail (its far end,
    None = its only child's joint), frame kind, rig bones and joint DOFs."""

    name: str
    parent: str | None
    joint: Anchor
    tail: Anchor | None
    frame: str
    bones: tuple[str, ...]
    dofs: tuple[DofSpec, ...]


@dataclass(frozen=True)
class SharedSpec:
    """Rig bones whose weights are shared along a chain of parts by position."""

    bones: tuple[str, ...]
    parts: tuple[str, ...]


@dataclass(frozen=True)
class SkeletonSpec:
    """A checked skeleton list; `parts` are ordered parents before children."""

    source: str
    parts: tuple[PartSpec, ...]
    shared: tuple[SharedSpec, ...]

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parts)

    def index(self, name: str) -> int:
        """Position of a part in `parts`."""
        try:
            return self.names.index(name)
        except ValueError:
            raise HitogataError(f"{self.source}: no part named {name!r}") from None

    @property
    def parents(self) -> tuple[int, ...]:
        """Index of each part's parent, -1 for the root."""
        names = self.names
        return tuple(-1 if p.parent is None else names.index(p.parent) for p in self.parts)

    @property
    def dof_names(self) -> tuple[str, ...]:
        """'part.dof' for every degree of freedom, in part order."""
        return tuple(f"{p.name}.{d.name}" for p in self.parts for d in p.dofs)


def default_skeleton_path() -> Path:
    """The skeleton list shipped with the package."""
    return Path(str(resources.files("hitogata").joinpath("data", DEFAULT_FILE)))


def parse_anchor(entry: Entry, key: str, value: Any) -> Anchor:
    """An anchor from `{bone=..}`, `{bones=[..]}`, `{between=[a, b], at=f}` or `{part=..}`."""
    sub = Entry(entry.source, f"{entry.where}: {key}", value, ("bone", "bones", "at", "between", "part"))
    kinds = [k for k in ("bone", "bones", "between", "part") if sub.has(k)]
    if len(kinds) != 1:
        sub.fail("give exactly one of bone, bones, between, part")
    kind = kinds[0]
    if kind in ("bone", "bones"):
        names = (sub.get("bone", str),) if kind == "bone" else sub.names("bones")
        end = sub.get("at", str, "head")
        if end not in ENDS or not names:
            sub.fail(f"at = {end!r}: allowed 'head' or 'tail' of one or more bones")
        return Anchor("bone", names, end=end)
    if kind == "between":
        names = sub.names("between")
        fraction = sub.number("at")
        if len(names) != 2 or not 0.0 <= fraction <= 1.0:
            sub.fail(f"between = {list(names)}, at = {fraction}: allowed two bones and 0 <= at <= 1")
        return Anchor("between", names, fraction=fraction)
    if sub.has("at"):
        sub.fail("'at' does not apply to a part's joint")
    return Anchor("part", (sub.get("part", str),))


def parse_dof(entry: Entry, index: int, value: Any) -> DofSpec:
    """One `{name, axis, min, max, rest}` DOF; degrees in the file, radians out."""
    sub = Entry(entry.source, f"{entry.where}: dof {index}", value, ("name", "axis", "min", "max", "rest"))
    name = sub.get("name", str)
    sub.where = f"{entry.where}: dof {name!r}"
    axis = sub.get("axis", str)
    if axis not in AXES:
        sub.fail(f"unknown axis {axis!r}; allowed: {', '.join(AXES)}")
    lo, hi = sub.number("min"), sub.number("max")
    if not lo < hi:
        sub.fail(f"min {lo:g} >= max {hi:g} degrees; allowed min < max")
    if sub.get("rest", (str, float), 0.0) == "measured":
        if axis.lstrip("-") != "hinge":
            sub.fail("rest = 'measured' needs a hinge axis (the bend between the part and its parent)")
        return DofSpec(name, axis, math.radians(lo), math.radians(hi), None)
    rest = sub.number("rest", 0.0)
    if not lo <= rest <= hi:
        sub.fail(f"rest {rest:g} outside [{lo:g}, {hi:g}] degrees")
    return DofSpec(name, axis, math.radians(lo), math.radians(hi), math.radians(rest))


def parse_part(source: str, index: int, value: Any) -> PartSpec:
    entry = Entry(source, f"part {index}", value, ("name", "parent", "joint", "tail", "frame", "bones", "dof"))
    name = entry.get("name", str)
    entry.where = f"part {name!r}"
    parent = entry.get("parent", str, None)
    frame = entry.get("frame", str, "bone")
    if frame not in FRAMES:
        entry.fail(f"frame = {frame!r}; allowed: {', '.join(FRAMES)}")
    joint = parse_anchor(entry, "joint", entry.get("joint", dict))
    if joint.kind == "part":
        entry.fail("a joint centre must be placed on the rig (bone, bones or between), not on a part")
    tail = parse_anchor(entry, "tail", entry.get("tail", dict)) if entry.has("tail") else None
    dofs = tuple(parse_dof(entry, k, d) for k, d in enumerate(entry.get("dof", list, [])))
    seen = set()
    for d in dofs:
        if d.name in seen:
            entry.fail(f"dof {d.name!r} given twice")
        seen.add(d.name)
    return PartSpec(name, parent, joint, tail, frame, entry.names("bones", []), dofs)


def topological(source: str, parts: list[PartSpec]) -> tuple[PartSpec, ...]:
    """Parts ordered parents first (file order among siblings), after checking the tree."""
    by_name: dict[str, PartSpec] = {}
    for p in parts:
        if p.name in by_name:
            raise HitogataError(f"{source}: part {p.name!r}: duplicate name")
        by_name[p.name] = p
    for p in parts:
        if p.parent is not None and p.parent not in by_name:
            raise HitogataError(f"{source}: part {p.name!r}: unknown parent {p.parent!r}")
    roots = [p.name for p in parts if p.parent is None]
    if not roots:
        raise HitogataError(f"{source}: no root part (every part has a parent); give one part no parent")
    if len(roots) > 1:
        raise HitogataError(
            f"{source}: two roots {roots[0]!r} and {roots[1]!r}; allowed exactly one part without parent"
        )
    children: dict[str, list[str]] = {p.name: [] for p in parts}
    for p in parts:
        if p.parent is not None:
            children[p.parent].append(p.name)
    order, stack = [], [roots[0]]
    while stack:
        name = stack.pop()
        order.append(by_name[name])
        stack.extend(reversed(children[name]))
    if len(order) < len(parts):
        reached = {p.name for p in order}
        stray = next(p.name for p in parts if p.name not in reached)
        raise HitogataError(f"{source}: part {stray!r}: its parents form a cycle, never reaching the root {roots[0]!r}")
    for p in order:
        if p.tail is None and len(children[p.name]) != 1:
            raise HitogataError(
                f"{source}: part {p.name!r}: has {len(children[p.name])} children, so it needs a 'tail'"
            )
        if p.tail is not None and p.tail.kind == "part" and p.tail.names[0] not in by_name:
            raise HitogataError(f"{source}: part {p.name!r}: tail names unknown part {p.tail.names[0]!r}")
    return tuple(p if p.tail is not None else _with_child_tail(p, children[p.name][0]) for p in order)


def _with_child_tail(part: PartSpec, child: str) -> PartSpec:
    return PartSpec(part.name, part.parent, part.joint, Anchor("part", (child,)), part.frame, part.bones, part.dofs)


def parse_shared(source: str, index: int, value: Any, parts: tuple[PartSpec, ...]) -> SharedSpec:
    entry = Entry(source, f"shared {index}", value, ("bones", "parts"))
    bones, names = entry.names("bones"), entry.names("parts")
    by_name = {p.name: p for p in parts}
    for k, name in enumerate(names):
        if name not in by_name:
            entry.fail(f"unknown part {name!r}")
        if k and by_name[name].parent != names[k - 1]:
            entry.fail(f"parts must form a chain: {name!r} is not the child of {names[k - 1]!r}")
    return SharedSpec(bones, names)


def load_skeleton_spec(path: str | Path | None = None) -> SkeletonSpec:
    """Read and check a skeleton list (the shipped one when `path` is None)."""
    source, doc = read_toml(default_skeleton_path() if path is None else path)
    top = Entry(source, "top level", doc, ("part", "shared"))
    raw = top.get("part", list)
    if not raw:
        top.fail("no [[part]] entries")
    parts = topological(source, [parse_part(source, k, v) for k, v in enumerate(raw)])
    shared = tuple(parse_shared(source, k, v, parts) for k, v in enumerate(top.get("shared", list, [])))
    owner: dict[str, str] = {}
    for where, bones in [(f"part {p.name!r}", p.bones) for p in parts] + [
        (f"shared {k}", s.bones) for k, s in enumerate(shared)
    ]:
        for bone in bones:
            if bone in owner:
                raise HitogataError(f"{source}: {where}: bone {bone!r} already given to {owner[bone]}")
            owner[bone] = where
    return SkeletonSpec(source, parts, shared)
