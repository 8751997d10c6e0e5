"""Body regions for the fit's residuals: which part of the body a scan point lies against.

Each skin vertex belongs to the region of the part carrying the rig bone with
its largest skin weight (the regions' parts: `hitogata.posing.body_split`,
"fit regions"); a scan point belongs to the region of its closest body point's nearest
corner. A region whose scan points stay far from the shape model's surface
is where the scan leaves the model's space (`cannot_follow`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.body.model import Body
from hitogata.posing.body_split import SPLITS, dominant_bone_parts, part_groups
from hitogata.posing.pose import poser_for

FIT_REGIONS = "fit regions"
REGIONS = tuple(SPLITS[FIT_REGIONS].groups)
# A region the model does not follow: its median distance at least FOLLOW_FACTOR times the whole
# scan's and above FOLLOW_FLOOR (a few mm: scan noise alone stays below it).
FOLLOW_FACTOR = 2.0
FOLLOW_FLOOR = 0.003  # m


def vertex_regions(body: Body) -> np.ndarray:
    """(V,) region index (into REGIONS) of each skin vertex."""
    poser = poser_for(body)
    return part_groups(FIT_REGIONS, poser.skeleton.names)[dominant_bone_parts(poser)]


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
