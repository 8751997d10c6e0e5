"""How far a close-fitting fabric must stretch per garment zone: along the body and across it.

A straight-grain piece laid on the skin has its lengthwise grain (warp)
along the body's long axis there and its crosswise grain (weft) round it.
Per skin triangle: the lengthwise direction is the long axis (joint → tail)
of the skeleton part owning its first corner (`posing.body_split.vertex_parts`), laid into the triangle's
plane; the crosswise direction is perpendicular to it in that plane. The
skin's stretch along a rest direction d is |F d| (F: the triangle's
deformation gradient, rest plane → posed), its engineering strain |F d| − 1;
the principal strain is the largest over all directions (`measure.strain`).
Per zone, the area-weighted 95th percentile of each (the stretch most of the
zone needs; a tight garment's fabric must reach it), per motion the largest
over its frames.

Zones a pattern maker names (right side for the limbs): across back and
across front (between the armpit folds, from 8 cm below the axilla up to
the shoulders, facing back / front), shoulder, elbow, knee and seat (as in
`measure.zones`), upper arm and thigh (the limb's skin outside those), and
the waist (trunk skin within 4 cm of the waist level).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from hitogata.body.model import Body
from hitogata.garment.ease import Surface, sampled_frames, skinned_surface
from hitogata.measure.landmarks import body_landmarks
from hitogata.measure.measurements import tape_skin
from hitogata.measure.strain import skin_strain
from hitogata.measure.zones import body_zones
from hitogata.motion.clip import MotionClip
from hitogata.posing.body_split import mainly_weighted, vertex_parts
from hitogata.posing.pose import poser_for
from hitogata.geometry.normals import triangle_normals

BAND_BELOW_AXILLA = 0.08  # m
WAIST_BAND = 0.04  # m each side of the waist level
FACING = 0.5  # the rest normal's backward (forward) component, across back (front)
GARMENT_ZONES = ("across_back", "across_front", "shoulder", "upper_arm", "elbow", "seat", "waist", "thigh", "knee")
PERCENTILE = 0.95
MAP_RANGE = 50.0  # %: the stretch maps' colour scale (fit report, viewer), the same for every motion


@dataclass(frozen=True)
class ZoneStretch:
    """One motion: per zone, the largest (over frames) 95th-percentile strain, %: lengthwise,
    crosswise, principal; and the smallest lengthwise and crosswise (compression, negative)."""

    motion: str
    zones: tuple[str, ...]
    lengthwise: np.ndarray
    crosswise: np.ndarray
    principal: np.ndarray
    lengthwise_min: np.ndarray
    crosswise_min: np.ndarray

    def rows(self) -> list[dict]:
        return [{"motion": self.motion, "zone": z, "lengthwise_pct": float(self.lengthwise[k]),
                 "crosswise_pct": float(self.crosswise[k]), "principal_pct": float(self.principal[k]),
                 "lengthwise_min_pct": float(self.lengthwise_min[k]), "crosswise_min_pct": float(self.crosswise_min[k])}
                for k, z in enumerate(self.zones)]


def garment_zones(body: Body) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """Face indices of each garment zone and the faces' lengthwise directions at rest (F, 3), found
    once per body and kept with it."""
    return body.prepared(_find_garment_zones)


def _find_garment_zones(body: Body) -> tuple[dict[str, np.ndarray], np.ndarray]:
    return _zones(body), _lengthwise(body)


def _zones(body: Body) -> dict[str, np.ndarray]:
    v, faces, rig = body.vertices, body.faces, body.rig
    centroid = v[faces].mean(axis=1)
    tri = v[faces]
    normal = triangle_normals(tri)
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)

    def follows(bones: tuple[str, ...]) -> np.ndarray:
        return mainly_weighted(body, [rig.index(b) for b in bones])[faces].all(axis=1)

    marks = body_landmarks(body)
    top = max(marks.acromion_left.at(v)[1], marks.acromion_right.at(v)[1])
    band = (centroid[:, 1] > marks.axilla - BAND_BELOW_AXILLA) & (centroid[:, 1] < top)
    limbs = follows(("upperarm01.L", "upperarm02.L", "upperarm01.R", "upperarm02.R"))
    back_x, front_x = abs(marks.fold_back_right.at(v)[0]), abs(marks.fold_front_right.at(v)[0])
    measured = body_zones(body)
    exclude = np.zeros(len(faces), bool)
    for name in ("shoulder_right", "elbow_right", "knee_right", "seat"):
        exclude[measured[name]] = True
    waist_y = 0.5 * (marks.waist_front.at(v)[1] + marks.waist_back.at(v)[1])
    trunk = tape_skin(body)["waist_girth"][faces].all(axis=1)  # the trunk tapes' skin: not the arms', legs'
    zones = {
        "across_back": band & ~limbs & (-normal[:, 2] >= FACING) & (np.abs(centroid[:, 0]) <= back_x),
        "across_front": band & ~limbs & (normal[:, 2] >= FACING) & (np.abs(centroid[:, 0]) <= front_x),
        "upper_arm": follows(("upperarm01.R", "upperarm02.R")) & ~exclude,
        "waist": trunk & (np.abs(centroid[:, 1] - waist_y) <= WAIST_BAND),
        "thigh": follows(("upperleg01.R", "upperleg02.R")) & ~exclude,
    }
    out = {}
    for name in GARMENT_ZONES:
        if name in zones:
            out[name] = np.flatnonzero(zones[name])
        else:
            out[name] = measured[name if name == "seat" else f"{name}_right"]
    return out


def _lengthwise(body: Body) -> np.ndarray:
    """(F, 3) unit lengthwise grain per face at rest: its main part's long axis in the face's plane."""
    poser = poser_for(body)
    sk = poser.skeleton
    axis = sk.tails - sk.joints
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    faces = body.faces
    part = vertex_parts(body)[faces[:, 0]]
    root = sk.parents < 0
    direction = np.where(root[part][:, None], np.array([0.0, 1.0, 0.0]), axis[part])
    tri = body.vertices[faces]
    normal = triangle_normals(tri)
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    along = direction - np.einsum("ij,ij->i", direction, normal)[:, None] * normal
    return along / np.linalg.norm(along, axis=1, keepdims=True)


def directional_strain(rest: np.ndarray, posed: np.ndarray, faces: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """(F,) engineering strain of each triangle along a rest direction lying in its plane."""
    e0 = np.stack([rest[faces[:, 1]] - rest[faces[:, 0]], rest[faces[:, 2]] - rest[faces[:, 0]]], axis=2)
    e1 = np.stack([posed[faces[:, 1]] - posed[faces[:, 0]], posed[faces[:, 2]] - posed[faces[:, 0]]], axis=2)
    gram = np.swapaxes(e0, 1, 2) @ e0
    coords = np.linalg.solve(gram, (np.swapaxes(e0, 1, 2) @ direction[:, :, None]))
    return np.linalg.norm(e1 @ coords, axis=(1, 2)) - 1.0


def area_percentile(values: np.ndarray, area: np.ndarray, q: float) -> float:
    """The area-weighted `q` quantile (0..1) of per-face values."""
    order = np.argsort(values)
    cumulative = np.cumsum(area[order]) / area.sum()
    return float(values[order][min(int(np.searchsorted(cumulative, q)), len(values) - 1)])


def zone_stretch(body: Body, name: str, clip: MotionClip, surface: Surface | None = None,
                 rate: float = 5.0) -> ZoneStretch:
    """The stretch each garment zone needs through one motion (sampled at `rate` frames per second)."""
    surface = surface or skinned_surface(body)
    zones, along = garment_zones(body)
    tri = body.vertices[body.faces]
    normal = triangle_normals(tri)
    area = 0.5 * np.linalg.norm(normal, axis=1)
    across = np.cross(normal / (2 * area[:, None]), along)
    frames = sampled_frames(clip, rate)
    posed = surface(clip.angles[frames], clip.root[frames])
    names = tuple(zones)
    out = {key: np.full(len(names), -np.inf) for key in ("l", "c", "p")}
    low = {key: np.full(len(names), np.inf) for key in ("l", "c")}
    for v in posed:
        strains = {"l": directional_strain(body.vertices, v, body.faces, along),
                   "c": directional_strain(body.vertices, v, body.faces, across),
                   "p": skin_strain(body.vertices, v, body.faces).stretch_max - 1.0}
        for k, zone in enumerate(names):
            faces = zones[zone]
            for key, values in strains.items():
                out[key][k] = max(out[key][k], 100 * area_percentile(values[faces], area[faces], PERCENTILE))
            for key in ("l", "c"):
                low[key][k] = min(low[key][k], 100 * area_percentile(strains[key][faces], area[faces], 1 - PERCENTILE))
    return ZoneStretch(name, names, out["l"], out["c"], out["p"], low["l"], low["c"])


def stretch_table(body: Body, motions: Mapping[str, MotionClip], surface: Surface | None = None,
                  rate: float = 5.0) -> list[ZoneStretch]:
    """`zone_stretch` for each named motion."""
    surface = surface or skinned_surface(body)
    return [zone_stretch(body, name, clip, surface, rate) for name, clip in motions.items()]


def stretch_csv(results: list[ZoneStretch]) -> str:
    """One row per motion and zone, percent."""
    rows = [r for z in results for r in z.rows()]
    keys = list(rows[0])
    return "\n".join([",".join(keys)] + [",".join(f"{r[k]:.4g}" if isinstance(r[k], float) else r[k] for k in keys)
                                         for r in rows]) + "\n"
