"""Muscles grouped by body region, for the slider folders: trunk, neck, then each side's limbs.

A muscle belongs to the region of the first joint it moves (the part whose
joint it turns); the side comes from that part's `_l`/`_r` suffix. A part no
region names (an edited skeleton list) falls into "Other muscles".
"""

from __future__ import annotations

from hitogata.muscles.geometry import MuscleSet

MIDLINE: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("Trunk", ("lumbar", "thoracic", "pelvis")),
    ("Neck and jaw", ("cervical", "head", "jaw")),
)
LIMB: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("shoulder", ("clavicle", "scapula", "upper_arm")),
    ("elbow and forearm", ("forearm",)),
    ("wrist", ("hand",)),
    ("thumb", ("thumb",)),
    ("fingers", ("index", "middle", "ring", "little")),
    ("hip", ("thigh",)),
    ("knee", ("shank",)),
    ("ankle and toes", ("foot", "toes")),
)
SIDES = (("_l", "Left"), ("_r", "Right"))
OTHER = "Other muscles"


def region_of(part: str) -> str:
    """The folder title for a muscle that moves `part`'s joint."""
    for title, prefixes in MIDLINE:
        if part.startswith(prefixes):
            return title
    for suffix, side in SIDES:
        if part.endswith(suffix):
            for region, prefixes in LIMB:
                if part.startswith(prefixes):
                    return f"{side} {region}"
    return OTHER


def folder_order() -> tuple[str, ...]:
    """Folder titles in display order."""
    limbs = tuple(f"{side} {region}" for _, side in SIDES for region, _ in LIMB)
    return tuple(title for title, _ in MIDLINE) + limbs + (OTHER,)


def muscle_groups(muscles: MuscleSet) -> dict[str, list[str]]:
    """Folder title → its muscles' names (list order), folders in display order, empty ones left out."""
    found: dict[str, list[str]] = {}
    for muscle in muscles.spec.muscles:
        found.setdefault(region_of(muscle.joints[0]), []).append(muscle.name)
    return {title: found[title] for title in folder_order() if title in found}


def slider_label(name: str, folder: str) -> str:
    """A muscle's name as a person reads it; the side is dropped where the folder already says it."""
    for suffix, side in SIDES:
        if name.endswith(suffix):
            base = name[: -len(suffix)].replace("_", " ")
            return base if folder.startswith(side) else f"{base} ({side.lower()})"
    return name.replace("_", " ")
