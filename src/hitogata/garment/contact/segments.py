"""Where a tubular garment lies on the body: its segment's levels and the stations between them.

A segment's levels are the body's measured girth planes (`measure.girth_planes`, ISO 8559-1; right
side for a limb): the leg's ankle (B), calf (C), knee (E) and thigh (G), the arm's wrist, elbow (⊥ the
bisector of upper arm and forearm through the elbow joint) and upper arm, the trunk's hip, waist,
underbust and chest. Each comes with the skin its tape may rest on (`measure.tape_skin`). The stations
are planes evenly spaced along the polyline through the levels' centres, their normals turned
gradually from one level's to the next, their in-plane bases carried along without twisting. A ring's
start is the body's section there (its convex hull, as a tape takes it) offset outward by a clearance,
sampled at even angles round the station's centre.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import maximum_filter1d

from hitogata.body.model import Body
from hitogata.errors import HitogataError
from hitogata.garment.contact.tube import Stations
from hitogata.measure.axes import JointSet, unit
from hitogata.measure.landmarks import body_landmarks
from hitogata.measure.measurements import girth_planes, tape_skin
from hitogata.posing.body_split import mainly_weighted
from hitogata.measure.sections import plane_basis, tape_girth
from hitogata.geometry.topology import topology

ELBOW_BONES = ("upperarm02.R", "lowerarm01.R")
SPACING = 0.01  # m between stations
MARGIN = (0.01, 0.01)  # m: the garment's reach beyond its first and last levels (more crosses other skin)
REACH = 2  # stations each side whose sections a ring's start clears
CLEARANCE = 0.004  # m: a ring's start outside the sections (2 mm let a 64-gon's chord cut a large calf's skin)


@dataclass(frozen=True, eq=False)
class Level:
    """A level's plane: origin on the segment's axis (3,), unit normal along the segment, the skin (V,) its
    tape rests on."""

    name: str
    origin: np.ndarray
    normal: np.ndarray
    skin: np.ndarray


def segment_levels(body: Body, vertices: np.ndarray, posed: JointSet, names: tuple[str, ...]) -> list[Level]:
    """The named levels (in order along the segment) on the body at `vertices` with joints `posed`."""
    rest = JointSet(body.rig.names, body.rig.heads)
    planes = girth_planes(vertices, body_landmarks(body), rest, posed)
    skins = tape_skin(body)
    out = []
    for name in names:
        if name == "elbow":
            shoulder, elbow, wrist = posed["upperarm01.R"], posed["lowerarm01.R"], posed["wrist.R"]
            normal = unit(unit(elbow - shoulder) + unit(wrist - elbow))
            skin = mainly_weighted(body, [i for i, bone in enumerate(body.rig.names) if bone.startswith(ELBOW_BONES)])
            out.append(Level(name, elbow, normal, skin))
            continue
        origin, normal, centre = planes[f"{name}_girth"]
        out.append(Level(name, centre - ((centre - origin) @ normal) * normal, normal, skins[f"{name}_girth"]))
    along = np.diff([level.origin for level in out], axis=0)
    for k, level in enumerate(out):  # every normal along the segment, first level to last
        direction = along[min(k, len(along) - 1)]
        if level.normal @ direction < 0:
            out[k] = Level(level.name, level.origin, -level.normal, level.skin)
    return out


def stations_along(levels: list[Level], spacing: float = SPACING, margin: tuple[float, float] = MARGIN,
                   count: int | None = None, first_u: np.ndarray | None = None) -> tuple[Stations, np.ndarray, np.ndarray]:
    """Stations every ~`spacing` along the levels' polyline, `margin` beyond its end levels (so each level's
    band lies under the garment), the arc length (m) of each station and of each level. count: that many
    stations evenly along it instead (a garment's rings carried into a posture, where the segment's length
    changes); first_u: the first station's in-plane direction u turned from this one (the last posture's:
    the rings' angles then keep their place on the body), default the plane's own basis."""
    origins = np.array([level.origin for level in levels])
    normals = np.array([level.normal for level in levels])
    origins = np.concatenate([[origins[0] - margin[0] * normals[0]], origins, [origins[-1] + margin[1] * normals[-1]]])
    normals = np.concatenate([normals[:1], normals, normals[-1:]])
    lengths = np.linalg.norm(np.diff(origins, axis=0), axis=1)
    level_arc = np.concatenate([[0.0], np.cumsum(lengths)])
    if count is None:
        count = max(int(np.ceil(level_arc[-1] / spacing)), 1) + 1
    arc = np.linspace(0.0, level_arc[-1], count)
    segment = np.clip(np.searchsorted(level_arc, arc, side="right") - 1, 0, len(origins) - 2)
    share = ((arc - level_arc[segment]) / lengths[segment])[:, None]
    points = origins[segment] + share * (origins[segment + 1] - origins[segment])
    normal = normals[segment] + share * (normals[segment + 1] - normals[segment])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    # bases carried from station to station (parallel transport: the least turn from each normal to the next)
    if first_u is None:
        _, u0, _ = plane_basis(normal[0])
    else:
        u0 = first_u - (first_u @ normal[0]) * normal[0]
        u0 = u0 / np.linalg.norm(u0)
    us = [u0]
    for n in normal[1:]:
        u = us[-1] - (us[-1] @ n) * n
        us.append(u / np.linalg.norm(u))
    u = np.array(us)
    return Stations(points, u, np.cross(normal, u)), arc, level_arc[1:-1]


def station_skin(levels: list[Level], arc: np.ndarray, level_arc: np.ndarray) -> list[np.ndarray]:
    """The skin a station's ring may rest on: its two neighbouring levels' together (the end levels' beyond
    them)."""
    k = np.clip(np.searchsorted(level_arc, arc, side="right") - 1, 0, len(levels) - 2)
    return [levels[i].skin | levels[i + 1].skin for i in k]


def section_hulls(vertices: np.ndarray, faces: np.ndarray, stations: Stations, skins: list[np.ndarray],
                  per_ring: int) -> tuple[np.ndarray, np.ndarray]:
    """Each station's section of the body (its convex hull, as a tape takes it): the hull's perimeter (M,)
    (m) and its distance (M, N) (m) from the station's centre at N even angles (the stations' u, v)."""
    topo = topology(faces)
    angle = 2 * np.pi * np.arange(per_ring) / per_ring
    rays = np.stack([np.cos(angle), np.sin(angle)], axis=1)
    girths, radii = [], []
    for j, (origin, u, v) in enumerate(zip(stations.origins, stations.u, stations.v)):
        tape = tape_girth(vertices, topo, origin, np.cross(u, v), origin, part=skins[j])
        if not np.isfinite(tape.girth):
            raise HitogataError(f"garment: the body has no section at station {j} of the segment")
        flat = np.stack([(tape.path - origin) @ u, (tape.path - origin) @ v], axis=1)
        girths.append(tape.girth)
        radii.append(_ray_hull(flat, rays))
    return np.array(girths), np.array(radii)


def body_rings(radii: np.ndarray, stations: Stations, clearance: float = CLEARANCE) -> np.ndarray:
    """The garment's start rings (M, N, 3) from the sections' hulls (their radii, `section_hulls`): at even
    angles round each station's centre, `clearance` outside the hulls of its station and the `REACH`
    stations each side (a bulge between two stations, a breast's or a calf's, stays inside the tube's
    triangles)."""
    per_ring = radii.shape[1]
    angle = 2 * np.pi * np.arange(per_ring) / per_ring
    rays = np.stack([np.cos(angle), np.sin(angle)], axis=1)
    radius = maximum_filter1d(radii, 2 * REACH + 1, axis=0, mode="nearest") + clearance
    coords = rays[None] * radius[..., None]
    return stations.place(coords)


def _ray_hull(hull: np.ndarray, rays: np.ndarray) -> np.ndarray:
    """Distance (R,) from the origin along each unit ray (R, 2) to a convex polygon (H, 2) round it."""
    a, b = hull, np.roll(hull, -1, axis=0)
    edge = b - a
    # origin + t ray = a + s edge  →  solve [ray, −edge] (t, s) = a
    det = rays[:, None, 0] * (-edge[None, :, 1]) - rays[:, None, 1] * (-edge[None, :, 0])
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (a[None, :, 0] * (-edge[None, :, 1]) - a[None, :, 1] * (-edge[None, :, 0])) / det
        s = (rays[:, None, 0] * a[None, :, 1] - rays[:, None, 1] * a[None, :, 0]) / det
    hit = (s >= -1e-9) & (s <= 1 + 1e-9) & (t > 0) & np.isfinite(t)
    t = np.where(hit, t, np.inf)
    out = t.min(axis=1)
    if not np.all(np.isfinite(out)):
        raise HitogataError("garment: a station's centre lies outside the body's section there")
    return out
