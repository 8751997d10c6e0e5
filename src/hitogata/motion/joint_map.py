"""Joint maps: which BVH joint drives which parts of the 65-part skeleton (editable TOML).

A map names the BVH's root joint and, per BVH joint, one part or a chain of
parts (parent first) sharing that joint's rotation equally — a motion-capture
spine of three joints drives 24 vertebrae. Shipped maps: `data/joint_maps/`
(CMU-style and Mixamo-style names); a BVH whose joints are hitogata's part
names (what `hitogata motion export` writes) maps onto itself.
"""

from __future__ import annotations

from typing import Any
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from hitogata.errors import HitogataError, excerpt
from hitogata.skeleton.placement import Skeleton
from hitogata.config import Entry, read_toml

IDENTITY = "hitogata"


@dataclass(frozen=True)
class JointMap:
    """root: the BVH root joint; chains: BVH joint name → parts it drives (parent first)."""

    source: str
    root: str
    chains: dict[str, tuple[str, ...]]


def bare(name: str) -> str:
    """A BVH joint name without a namespace prefix ('mixamorig:LeftArm' → 'LeftArm')."""
    return name.rsplit(":", 1)[-1]


def shipped_joint_maps() -> dict[str, Path]:
    """The shipped maps by name."""
    folder = resources.files("hitogata") / "data" / "joint_maps"
    return {p.name.removesuffix(".toml"): Path(str(p)) for p in folder.iterdir() if p.name.endswith(".toml")}


def load_joint_map(path: str | Path, skeleton: Skeleton) -> JointMap:
    """Read and check a map against the skeleton's parts."""
    source, doc = read_toml(path)
    top = Entry(source, "top level", doc, ("root", "parts"))
    root = top.get("root", str)
    table = Entry(source, "[parts]", top.get("parts", dict), tuple(top.get("parts", dict)))
    chains: dict[str, Any] = {}
    owner: dict[str, Any] = {}
    for joint, value in table.table.items():
        parts = (value,) if isinstance(value, str) else value
        if not (isinstance(parts, (list, tuple)) and parts and all(isinstance(p, str) for p in parts)):
            table.fail(f"{joint} = {value!r}: allowed a part name or a list of part names")
        for k, part in enumerate(parts):
            if part not in skeleton.names:
                table.fail(f"{joint}: unknown part {part!r}; allowed the skeleton's parts, e.g. upper_arm_l")
            if part in owner:
                table.fail(f"{joint}: part {part!r} is already driven by {owner[part]}")
            if part == skeleton.names[0]:
                table.fail(f"{joint}: the root part {part!r} follows the BVH root ({root}); map it nowhere")
            if k and skeleton.parents[skeleton.index(part)] != skeleton.index(parts[k - 1]):
                table.fail(f"{joint}: {part!r} is not the child of {parts[k - 1]!r}; allowed a chain, parent first")
            owner[part] = joint
        chains[joint] = tuple(parts)
    return JointMap(source, root, chains)


def identity_map(skeleton: Skeleton) -> JointMap:
    """Every part driven by the BVH joint of its own name."""
    return JointMap(IDENTITY, skeleton.names[0], {n: (n,) for n in skeleton.names[1:]})


def choose_joint_map(names: tuple[str, ...], skeleton: Skeleton, requested: str | Path | None = None,
                     source: str = "BVH") -> JointMap:
    """The requested map (a shipped name or a TOML path), or the one matching the most BVH joints (of file `source`)."""
    shipped = shipped_joint_maps()
    if requested is not None:
        if str(requested) == IDENTITY:
            return identity_map(skeleton)
        return load_joint_map(shipped.get(str(requested), requested), skeleton)
    joints = {bare(n) for n in names}
    candidates = [identity_map(skeleton)] + [load_joint_map(p, skeleton) for p in shipped.values()]
    scored = [(len(joints & set(m.chains)) + (m.root in joints), -k, m) for k, m in enumerate(candidates)]
    best = max(scored, key=lambda s: s[:2])
    if best[0] < 4:
        raise HitogataError(
            f"{source}: joints {', '.join(excerpt(j, 20) for j in sorted(joints)[:4])}…: no joint map matches them; allowed a map "
            f"({', '.join([IDENTITY, *shipped])} or a TOML file like data/joint_maps/cmu.toml)")
    return best[2]
