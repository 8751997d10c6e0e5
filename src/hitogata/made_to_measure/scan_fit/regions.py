"""Body regions for the fit's residuals: which part of the body a scan point lies against.

Each skin vertex belongs to the region of the bone with its largest skin
weight; a scan point belongs to the region of its closest body point's nearest
corner. A region whose scan points stay far from the shape model's surface
is where the scan leaves the model's space (`cannot_follow`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.body.model import Body

LIMB_PARTS = {"arm": ("upperarm", "lowerarm"), "hand": ("wrist", "metacarpal", "finger"),
              "leg": ("upperleg", "lowerleg"), "foot": ("foot", "toe")}
TRUNK_BONES = ("spine", "breast", "pelvis", "clavicle", "shoulder", "root")
REGIONS = ("head and neck", "trunk", *(f"{side} {part}" for part in LIMB_PARTS for side in ("left", "right")))
# A region the model does not follow: its median distance at least FOLLOW_FACTOR times the whole
# scan's and above FOLLOW_FLOOR (a few mm: scan noise alone stays below it).
FOLLOW_FACTOR = 2.0
FOLLOW_FLOOR = 0.003  # m


def bone_region(bone: str) -> str:
    """The region a rig bone's skin belongs to (MakeHuman's .L is the body's left)."""
    for part, prefixes in LIMB_PARTS.items():
        if bone.startswith(prefixes):
            return f"{'left' if bone.endswith('.L') else 'right'} {part}"
    return "trunk" if bone.startswith(TRUNK_BONES) else "head and neck"


def vertex_regions(body: Body) -> np.ndarray:
    """(V,) region index (into REGIONS) of each skin vertex."""
    dominant = np.asarray(body.skin_weights.argmax(axis=1)).ravel()
    of_bone = np.array([REGIONS.index(bone_region(name)) for name in body.rig.names])
    return of_bone[dominant]


@dataclass(frozen=True)
class RegionResidual:
    """Scan → body distances of one region's scan points, m; `outside`: the median signed distance
    (positive: the scan lies outside the body there)."""

    region: str
    points: int
    median: float
    p95: float
    outside: float


def region_residuals(region: np.ndarray, distance: np.ndarray, signed: np.ndarray) -> list[RegionResidual]:
    """Per region with scan points: their count, median and 95th-percentile distance, median signed distance."""
    out = []
    for k, name in enumerate(REGIONS):
        mine = region == k
        if np.any(mine):
            out.append(RegionResidual(name, int(np.count_nonzero(mine)), float(np.median(distance[mine])),
                                      float(np.percentile(distance[mine], 95)), float(np.median(signed[mine]))))
    return out


def cannot_follow(residuals: list[RegionResidual], overall_median: float) -> list[str]:
    """The regions whose median distance is well above the whole scan's (`FOLLOW_FACTOR`, `FOLLOW_FLOOR`)."""
    limit = max(FOLLOW_FLOOR, FOLLOW_FACTOR * overall_median)
    return [r.region for r in residuals if r.median > limit]
