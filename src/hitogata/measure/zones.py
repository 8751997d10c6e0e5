"""Body zones where garments strain, and skin-strain figures for each (percent).

Zones are vertex sets of the rest body, chosen from the skinning weights and
the rig (docs/measurements.md): round a joint, the skin within a radius of the
joint centre that mainly follows the bones meeting there (elbow, knee,
shoulder); on the trunk, the backward-facing skin that mainly follows given
bones (the back: the thoracic spine; the seat: the pelvis and hip); "mainly":
`hitogata.posing.body_split.mainly_weighted`, where the parts each zone lies
on are named with the body's other splits. A face
belongs to a zone when its three corners do. On the fine skin
(`hitogata.skin.fine_skin`) a face belongs to the zone of the coarse face
it lies in, so the zones are the same skin measured finer.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.body.model import Body
from hitogata.errors import HitogataError
from hitogata.measure.strain import SkinStrain
from hitogata.geometry.normals import vertex_normals
from hitogata.posing.body_split import mainly_weighted
from hitogata.skin.fine_skin import body_fine_skin


@dataclass(frozen=True)
class JointZone:
    """Skin within `radius` × stature of a joint centre, weighted mainly to `bones`."""

    joint: str
    bones: tuple[str, ...]
    radius: float


@dataclass(frozen=True)
class BackZone:
    """Backward-facing skin (rest normal's −z part ≥ `facing`) weighted mainly to `bones`."""

    bones: tuple[str, ...]
    facing: float


ZONES: dict[str, JointZone | BackZone] = {
    "back": BackZone(("spine01", "spine02", "spine03"), facing=0.5),
    "seat": BackZone(("pelvis.L", "pelvis.R", "upperleg01.L", "upperleg01.R", "spine05", "root"), facing=0.3),
    "shoulder_right": JointZone("upperarm01.R", ("clavicle.R", "shoulder01.R", "upperarm01.R", "upperarm02.R"), 0.06),
    "shoulder_left": JointZone("upperarm01.L", ("clavicle.L", "shoulder01.L", "upperarm01.L", "upperarm02.L"), 0.06),
    "elbow_right": JointZone("lowerarm01.R", ("upperarm02.R", "lowerarm01.R", "lowerarm02.R"), 0.042),
    "elbow_left": JointZone("lowerarm01.L", ("upperarm02.L", "lowerarm01.L", "lowerarm02.L"), 0.042),
    "knee_right": JointZone("lowerleg01.R", ("upperleg02.R", "lowerleg01.R", "lowerleg02.R"), 0.055),
    "knee_left": JointZone("lowerleg01.L", ("upperleg02.L", "lowerleg01.L", "lowerleg02.L"), 0.055),
}
ZONE_NAMES = tuple(ZONES)


@dataclass(frozen=True)
class ZoneStrain:
    """Strain figures of one zone, percent; means are weighted by rest area."""

    stretch_mean: float  # mean largest principal strain (λ1 − 1)
    stretch_p95: float  # 95th percentile (by area) of the largest principal strain
    stretch_max: float
    compression_mean: float  # mean smallest principal strain (λ2 − 1)
    area_change: float  # zone's area now over its rest area, − 1


def body_zones(body: Body) -> dict[str, np.ndarray]:
    """Face indices of each zone on this body, found once on its rest shape and kept with it."""
    return body.prepared(find_zones)


def find_zones(body: Body) -> dict[str, np.ndarray]:
    """Face indices of each zone, found on the body's rest shape."""
    return {name: zone_faces(body, zone) for name, zone in ZONES.items()}


def zone_faces(body: Body, zone: JointZone | BackZone) -> np.ndarray:
    rig, v = body.rig, body.vertices
    inside = mainly_weighted(body, [rig.index(bone) for bone in zone.bones])
    if isinstance(zone, JointZone):
        centre = rig.heads[rig.index(zone.joint)]
        inside &= np.linalg.norm(v - centre, axis=1) <= zone.radius * body.stature
    else:
        inside &= -vertex_normals(v, body.faces)[:, 2] >= zone.facing
    return np.flatnonzero(inside[body.faces].all(axis=1))


def zone_strain(strain: SkinStrain, faces: np.ndarray) -> ZoneStrain:
    """Summary figures (percent) of the strain over the given faces."""
    area = strain.rest_area[faces]
    stretch = strain.strain_max_percent[faces]
    order = np.argsort(stretch)
    cumulative = np.cumsum(area[order]) / area.sum()
    return ZoneStrain(
        stretch_mean=float(np.average(stretch, weights=area)),
        stretch_p95=float(stretch[order][np.searchsorted(cumulative, 0.95)]),
        stretch_max=float(stretch.max()),
        compression_mean=float(np.average((strain.stretch_min[faces] - 1.0) * 100.0, weights=area)),
        area_change=float((np.sum(area * strain.area_ratio[faces]) / area.sum() - 1.0) * 100.0),
    )


def fine_zones(body: Body) -> dict[str, np.ndarray]:
    """Face indices of each zone on the body's fine skin."""
    parent = body_fine_skin(body).parent
    return {name: np.flatnonzero(np.isin(parent, faces)) for name, faces in body_zones(body).items()}


def zone_strains(body: Body, strain: SkinStrain) -> dict[str, ZoneStrain]:
    """Summary figures of every zone of `body`, for a strain on its skin or on its fine skin."""
    n = len(strain.rest_area)
    if n == len(body.faces):
        zones = body_zones(body)
    elif n == len(body_fine_skin(body).faces):
        zones = fine_zones(body)
    else:
        allowed = f"{len(body.faces)} (the skin) or {len(body_fine_skin(body).faces)} (the fine skin)"
        raise HitogataError(f"strain of {n} faces: allowed {allowed}")
    return {name: zone_strain(strain, faces) for name, faces in zones.items()}
