"""A dressed garment through a motion: each sampled frame's contact solved from the last frame's.

The body is skinned onto the motion's skeleton (dual quaternions, as `hitogata ease` takes it) at the
sampled frames. On each frame the garment's levels and stations are found on the posed skin as on the
standing body, the same number of stations (the garment's rings are carried along: where the segment
lengthens, over a bent knee, its wale stretches), and on a limb the tissue is meshed again round the
posed bones. The garment is the standing one (its relaxed sizes and rest shape: an ease is taken on
the standing girths, not a frame's), and the solve starts warm: the last frame's garment in its rings'
planes and the tissue's displacements, each carried in its station's frame into the new posture, with
the standing solve's barrier stiffness κ. On a limb each garment point stays where it lay unless the
carried tissue's own surface now comes within half a barrier's reach of it along its ray, or past it:
then it starts that far out from the surface (`onto_tissue`: where the hip's flexion brings the gluteal
fold into a section, the garment starts on the fold, not 25 mm out on the section's hull). Else, and on
the rigid body, each point is moved out or in with the skin's section under it (`followed`). The
garment is settled on the body held still first, then with the tissue (`dressing.solve`); where the
carried κ is too weak for the new posture's contacts, Newton raises it on the way and settles the answer
at the carried κ again (`equilibrium.settle`). Where every start crosses or touches the posed skin (a fast
move between frames), or Newton sticks from it even so, the frame starts cold as the standing solve does:
the rings outside the sections, shrunk on (decision 0029).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import maximum_filter1d

from hitogata.body.model import Body
from hitogata.elastic.materials import Materials
from hitogata.errors import HitogataError
from hitogata.garment.contact.answers import GarmentContact, garment_contact
from hitogata.garment.contact.dressing import Dressing, Posture, place, solve
from hitogata.garment.contact.equilibrium import CCD_GAP, DHAT, SETTLE, crossings
from hitogata.garment.contact.segments import body_rings
from hitogata.garment.contact.tissue import ALONG, LimbTissue, limb_tissue
from hitogata.garment.contact.tube import Stations, Tube
from hitogata.garment.ease import sampled_frames
from hitogata.geometry.raycast import ray_triangle
from hitogata.motion.clip import MotionClip
from hitogata.posing.pose import poser_for
from hitogata.body.rig import carried_heads, carrying_parts

# m: a carried garment's start this much further out than the skin's move: none first, then half the
# barrier's reach (the carried tissue's facets and the garment's rings differ between the tissue's sections)
LIFTS = (0.0, 0.5 * DHAT)
# m: a garment point the carried tissue's own surface comes within this of along its ray, or past, starts this far
# out (where the barrier's contact settles, `equilibrium.SETTLE`)
ON_TISSUE_LIFT = SETTLE * DHAT
# m: a laid ring closer than this to the carried tissue's surface is lifted as a crossing one is (a start within
# CCD's gap cannot be moved)
NEAREST = 2 * CCD_GAP
ON_TISSUE_MOST = 16 * DHAT  # m: the furthest a ring crossing the tissue's surface is lifted (then started as it lay)


@dataclass(frozen=True, eq=False)
class MotionContact:
    """A garment through one motion: the sampled times (T,) s, each frame's contact answers and whether
    the frame started warm (from the last one's equilibrium)."""

    times: np.ndarray
    frames: tuple[GarmentContact, ...]
    warm: tuple[bool, ...]


def postures(body: Body, clip: MotionClip, rate: float) -> tuple[np.ndarray, list[Posture]]:
    """The motion's frames sampled at `rate` per second: their times (T,) and the body's postures (skin
    by dual-quaternion skinning, the rig's bones carried by their parts)."""
    frames = sampled_frames(clip, rate)
    poser = poser_for(body)
    pose = poser.kinematics.pose(clip.angles[frames], root=clip.root[frames])
    vertices = poser.pose_many(clip.angles[frames], "dqs", clip.root[frames])
    parts = carrying_parts(body.rig.heads, poser.skeleton.joints)
    heads = carried_heads(body.rig.heads, parts, pose.rotations, pose.translations)
    tails = carried_heads(body.rig.tails, parts, pose.rotations, pose.translations)
    return clip.times[frames], [Posture(vertices[k], heads[k], tails[k]) for k in range(len(frames))]


def carried(points: np.ndarray, sections: np.ndarray, before: Stations, after: Stations) -> np.ndarray:
    """Vectors (P, 3) in the frames (u, v, axis) of their stations `sections` (P,) before, turned into the
    same stations' frames after."""
    local = np.stack([np.einsum("pi,pi->p", points, getattr(before, name)[sections]) for name in ("u", "v")]
                     + [np.einsum("pi,pi->p", points, before.axis[sections])], axis=1)
    return (local[:, :1] * after.u[sections] + local[:, 1:2] * after.v[sections]
            + local[:, 2:] * after.axis[sections])


def followed(coords: np.ndarray, before: np.ndarray, after: np.ndarray, lift: float) -> np.ndarray:
    """In-plane garment coordinates (M, N, 2) moved out or in with the skin: each point along its ray by
    the change of the sections' hull radii there, from `before` to `after` (M, N) at N even angles
    (periodic interpolation), and `lift` further out. A ring takes the largest change of its own section
    and its neighbours' within the tissue's spacing (`tissue.ALONG`): the tissue between its sections is
    their straight join, and a ring between two sections must clear it however the skin moved there."""
    per_ring = before.shape[1]
    radius = np.linalg.norm(coords, axis=2)
    angle = np.mod(np.arctan2(coords[..., 1], coords[..., 0]), 2 * np.pi) * per_ring / (2 * np.pi)
    low = np.floor(angle).astype(int) % per_ring
    share = angle - np.floor(angle)
    change = maximum_filter1d(after - before, 2 * ALONG - 1, axis=0, mode="nearest")
    rows = np.arange(len(coords))[:, None]
    shift = (1 - share) * change[rows, low] + share * change[rows, (low + 1) % per_ring]
    return coords * ((radius + shift + lift) / radius)[..., None]


def onto_tissue(coords: np.ndarray, tube: Tube, tissue: LimbTissue, nodes: np.ndarray, missed: np.ndarray) -> np.ndarray:
    """In-plane garment coordinates (M, N, 2) kept where they lay, but moved out along their rays from their
    stations' centres (`tube`'s) where the tissue's outer surface (its nodes at `nodes` (T, 3)) now comes
    within `ON_TISSUE_LIFT` of them or past them: to that far beyond where the ray leaves the surface. A ring
    whose triangles then cross the surface (its chords cut the tissue's ridges or a fold) or come within
    `NEAREST` of it is lifted twice as far, and again, up to `ON_TISSUE_MOST`. A point whose ray meets no triangle of the surface near its
    station lies at `missed`'s radius (M, N, 2: the same rays), lifted with its ring beyond the first lift."""
    reach = tissue_reach(coords, tube.stations, tissue, nodes)
    radius = np.linalg.norm(coords, axis=2)
    unit = coords / radius[..., None]
    missed_radius = np.linalg.norm(missed, axis=2)
    lift = np.full(len(coords), ON_TISSUE_LIFT)
    while True:
        laid = np.where(np.isfinite(reach), reach + lift[:, None], missed_radius + lift[:, None] - ON_TISSUE_LIFT)
        placed = unit * np.maximum(laid, radius)[..., None]
        rings = crossing_rings(tube, tube.stations.place(placed).reshape(-1, 3), nodes, tissue.body.faces,
                               NEAREST)
        if not rings.size or lift[rings].max() >= ON_TISSUE_MOST:
            return placed
        lift[rings] *= 2


def tissue_reach(coords: np.ndarray, stations: Stations, tissue: LimbTissue, nodes: np.ndarray) -> np.ndarray:
    """(M, N) m: how far from its station's centre each garment point's ray (in-plane coordinates `coords`
    (M, N, 2)) leaves the tissue's outer surface (its nodes at `nodes`); NaN where it meets none of its
    triangles near the station."""
    per_ring = coords.shape[1]
    unit = coords / np.linalg.norm(coords, axis=2)[..., None]
    rays = unit[..., :1] * stations.u[:, None] + unit[..., 1:] * stations.v[:, None]  # (M, N, 3)
    faces = tissue.body.faces
    station_of_face = tissue.stations[tissue.section[faces]]  # (F, 3)
    first, last = station_of_face.min(axis=1), station_of_face.max(axis=1)
    reach = np.full(coords.shape[:2], np.nan)
    for ring, origin in enumerate(stations.origins):
        near = faces[(first <= ring + ALONG) & (last >= ring - ALONG)]  # the tissue between its sections round it
        pairs = np.repeat(rays[ring], len(near), axis=0)
        triangles = np.tile(nodes[near], (per_ring, 1, 1))
        # an end ring's plane is near the tissue's end section's: its rays may run along the surface's edges
        # there, so they are cast a micrometre either side of it too
        for shift in (0.0, 1e-6, -1e-6):
            if not np.isnan(reach[ring]).any():
                break
            t = ray_triangle(origin + shift * stations.axis[ring], pairs, triangles).reshape(per_ring, len(near))
            farthest = np.where(np.isfinite(t), t, -np.inf).max(axis=1, initial=-np.inf)  # where the ray leaves it
            reach[ring] = np.where(np.isnan(reach[ring]) & np.isfinite(farthest), farthest, reach[ring])
    return reach


def crossing_rings(tube: Tube, garment: np.ndarray, skin: np.ndarray, skin_faces: np.ndarray,
                   gap: float = 0.0) -> np.ndarray:
    """The rings (sorted) of the garment's triangles (`garment` (V, 3) on `tube`) that cross the skin's or
    come within `gap` (m) of it: the exact test on the whole garment, then on halves of its rings where it
    finds a crossing."""
    ring_of_face = tube.faces.min(axis=1) // tube.per_ring
    found: list[int] = []

    def search(low: int, high: int) -> None:
        chosen = tube.faces[(ring_of_face >= low) & (ring_of_face < high)]
        if not len(chosen) or not crossings(garment, chosen, skin, skin_faces, gap):
            return
        if high - low == 1:  # a band's triangles join its ring to the next
            found.extend([low, min(low + 1, tube.n_rings - 1)])
            return
        middle = (low + high) // 2
        search(low, middle)
        search(middle, high)

    search(0, tube.n_rings)
    return np.unique(np.asarray(found, dtype=np.int64))


def dress_frame(previous: Dressing, posture: Posture, materials: Materials | None = None) -> tuple[Dressing, bool]:
    """The garment of a solved dressing on the body in the next `posture`, from the previous equilibrium
    (see the module note); whether the warm start was taken."""
    body, spec, old = previous.body, previous.spec, previous.tube
    at = place(body, spec, posture, carried=old.stations)
    tube = Tube(at.stations, old.per_ring, old.faces, old.membrane, old.relaxed)
    tissue: LimbTissue | None = None
    tissue_start = None
    if previous.tissue is not None and previous.tissue_nodes is not None:
        tissue = limb_tissue(body, spec.segment, at.stations, at.radii, materials, (posture.heads, posture.tails))
        moved = previous.tissue_nodes - previous.tissue.body.points
        sections = previous.tissue.stations[previous.tissue.section]
        tissue_start = tissue.body.points + carried(moved, sections, old.stations, at.stations)
    coords = old.stations.coordinates(previous.garment.reshape(old.n_rings, old.per_ring, 3))
    before = at.radii if previous.hull_radii is None else previous.hull_radii  # the skin's sections it lay on
    args = (body, spec, posture, at.levels, at.arc, at.level_arc, at.radii, tube, tissue)
    starts = [followed(coords, before, at.radii, lift) for lift in LIFTS]  # as it lay, then lifted a little
    if tissue is not None and tissue_start is not None:  # first just outside the carried tissue's own surface
        starts.insert(0, onto_tissue(coords, tube, tissue, tissue_start, starts[0]))
    for placed in starts:
        start = at.stations.place(placed).reshape(-1, 3)
        try:
            warm = solve(*args, start, stiffness=previous.barrier_stiffness, tissue_start=tissue_start)
        except HitogataError:
            continue
        if warm.converged:
            return warm, True
    # the carried garment crosses the posed skin (or Newton stuck from it): shrunk on again from outside
    return solve(*args, body_rings(at.radii, at.stations).reshape(-1, 3)), False


def dress_through(standing: Dressing, clip: MotionClip, rate: float,
                  materials: Materials | None = None) -> MotionContact:
    """The garment of a standing dressing through a motion sampled at `rate` frames per second, each
    frame solved from the last (the first from the standing equilibrium)."""
    times, frames = postures(standing.body, clip, rate)
    answers, warm = [], []
    previous = standing
    for posture in frames:
        previous, was_warm = dress_frame(previous, posture, materials)
        answers.append(garment_contact(previous, laplace=False))
        warm.append(was_warm)
    return MotionContact(times, tuple(answers), tuple(warm))
