"""A dressed garment through a motion: each sampled frame's contact solved from the last frame's.

The body is skinned onto the motion's skeleton (dual quaternions, as `hitogata ease` takes it) at the
sampled frames. On each frame the garment's levels and stations are found on the posed skin as on the
standing body, the same number of stations (the garment's rings are carried along: where the segment
lengthens, over a bent knee, its wale stretches), and on a limb the tissue is meshed again round the
posed bones. The garment is the standing one (its relaxed sizes and rest shape: an ease is taken on
the standing girths, not a frame's), and the solve starts warm: the last frame's garment in its rings'
planes and the tissue's displacements, each carried in its station's frame into the new posture, each
garment point moved out or in with the skin's section under it (`followed`), with the standing solve's
barrier stiffness κ. Where that start crosses or touches the posed skin even lifted half a barrier's
reach (a fast move between frames), or Newton sticks from it, the frame starts cold as the standing solve does: the rings outside
the sections, shrunk on (decision 0029).
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
from hitogata.garment.contact.equilibrium import DHAT
from hitogata.garment.contact.segments import body_rings
from hitogata.garment.contact.tissue import ALONG, LimbTissue, limb_tissue
from hitogata.garment.contact.tube import Stations, Tube
from hitogata.garment.ease import sampled_frames
from hitogata.motion.clip import MotionClip
from hitogata.posing.pose import poser_for
from hitogata.body.rig import carried_heads, carrying_parts

# m: a carried garment's start this much further out than the skin's move: none first, then half the
# barrier's reach (the carried tissue's facets and the garment's rings differ between the tissue's sections)
LIFTS = (0.0, 0.5 * DHAT)


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
    for lift in LIFTS:  # as it lay, then lifted off the skin a little
        start = at.stations.place(followed(coords, before, at.radii, lift)).reshape(-1, 3)
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
