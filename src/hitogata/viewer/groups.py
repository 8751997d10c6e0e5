"""Muscles grouped by body region, for the slider folders: trunk, neck, then each side's limbs.

A muscle belongs to the folder of the first joint it moves (the part whose
joint it turns): the folders' parts are `hitogata.posing.body_split`'s
"muscle folders". A part no folder names (an edited skeleton list) falls
into "Other muscles".
"""

from __future__ import annotations

from hitogata.muscles.geometry import MuscleSet
from hitogata.posing.body_split import SPLITS, part_groups

FOLDERS = tuple(SPLITS["muscle folders"].groups)
SIDES = (("_l", "Left"), ("_r", "Right"))
OTHER = "Other muscles"


def region_of(part: str) -> str:
    """The folder title for a muscle that moves `part`'s joint."""
    g = int(part_groups("muscle folders", (part,))[0])
    return FOLDERS[g] if g >= 0 else OTHER


def folder_order() -> tuple[str, ...]:
    """Folder titles in display order."""
    return (*FOLDERS, OTHER)


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
