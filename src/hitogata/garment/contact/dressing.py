"""A tubular garment put on the body: the contact pressure of the fabric on the real skin.

The garment starts as rings just outside the standing body's sections along its segment
(`segments.body_rings`) with its relaxed size as sewn, so it is stretched from the start, and Newton
with CCD pulls it onto the skin (`equilibrium.settle`): the loose fit shrunk to its relaxed size. The
skin within `REACH` of the garment's start is the rigid body's contact surface (both legs' skin where
they are near: the garment never passes into the other limb either). On a limb the body is soft by
default: the garment presses on the limb's tissue (`tissue`: a tet mesh between bone and skin, the
materials file's moduli) solved with it in one Newton, and the tissue's contact forces are carried to
the skin's vertices under it. The trunk is held rigid (its tissue model is the whole body's lattice,
too coarse for millimetres: decision 0020).

The garment's courses stay in their planes (`tube`); the force that holds them there is what friction
on the skin must supply (`spread_on_surface` puts it on the skin, so the garment's loads on the body sum to
zero).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from hitogata.body.model import Body
from hitogata.errors import HitogataError
from hitogata.elastic.materials import Materials
from hitogata.garment.contact.equilibrium import ContactBody, settle
from hitogata.garment.contact.readings import LevelReader
from hitogata.garment.contact.segments import (
    SPACING,
    Level,
    body_rings,
    section_hulls,
    segment_levels,
    station_skin,
    stations_along,
)
from hitogata.garment.contact.tissue import LIMB_BONES, LimbTissue, limb_tissue
from hitogata.garment.contact.spec import GarmentSpec
from hitogata.garment.contact.tube import Stations, Tube, build_tube
from hitogata.made_to_measure.scan_fit.closest import SurfaceQuery
from hitogata.measure.axes import JointSet

REACH = 0.03  # m: skin within this of the garment's start is the contact surface


@dataclass(frozen=True, eq=False)
class Dressing:
    """A garment on the body, solved: the body, its levels, the stations' and levels' arc lengths (m), the
    garment's tube, its vertices (G, 3) and the skin's push on each (G, 3) (N), the skin (V, 3), the contact force on each skin vertex (V, 3)
    (N), the skin's share of holding the courses (V, 3) (N), the skin vertices of the contact surface (V,)
    bool, Newton's iterations, whether it converged and the least garment–skin distance (m)."""

    body: Body
    spec: GarmentSpec
    levels: list[Level]
    level_arc: np.ndarray
    arc: np.ndarray
    tube: Tube
    garment: np.ndarray
    garment_force: np.ndarray  # (G, 3) N: the skin's push on each garment vertex
    skin: np.ndarray
    force: np.ndarray
    friction: np.ndarray  # (V, 3) N: the skin's share of holding the garment's courses in their planes
    contact_skin: np.ndarray
    iterations: int
    converged: bool
    min_distance: float
    tissue: LimbTissue | None = None  # the soft limb under the garment (None: the rigid body)
    tissue_nodes: np.ndarray | None = None  # (T, 3) its nodes at equilibrium
    barrier_stiffness: float = float("nan")  # the barrier's κ of the solve (a motion's frames keep it)
    hull_radii: np.ndarray | None = None  # (M, N) m: the body's sections round the stations (`section_hulls`)


def relaxed_at_stations(spec: GarmentSpec, girths: np.ndarray, arc: np.ndarray, level_arc: np.ndarray) -> np.ndarray:
    """The relaxed circumference (m) at each station: the ease × the body's girth there, the levels'
    relaxed circumferences interpolated along the segment, or the garment mesh's section there; refused (one line) where the fabric would be
    stretched beyond the strain its tensile test reached."""
    if spec.mesh is not None:  # its openings at the first and last stations (`garment_mesh`)
        relaxed = spec.mesh.relaxed(arc / arc[-1])
    elif spec.relaxed is not None:
        relaxed = np.interp(arc, level_arc, [spec.relaxed[level] for level in spec.levels])
    else:
        relaxed = (1.0 + float(spec.ease or 0.0)) * girths
    strain = girths / relaxed - 1.0
    worst = int(np.argmax(strain))
    tested = spec.course.tested_strain
    if strain[worst] > tested:
        level = spec.levels[int(np.argmin(np.abs(level_arc - arc[worst])))]
        value = f"{100 * (spec.ease or 0):+.0f}%" if spec.ease is not None else f"{100 * relaxed[worst]:.1f} cm"
        raise HitogataError(f"{spec.where(level)}: {value} is smaller than the fabric can stretch to near the "
                            f"{level} ({100 * girths[worst]:.1f} cm round: {100 * strain[worst]:.0f} % strain); "
                            f"allowed at least {100 * girths[worst] / (1 + tested):.1f} cm there (the fabric's "
                            f"test reaches {100 * tested:.0f} %)")
    return relaxed


@dataclass(frozen=True, eq=False)
class Posture:
    """The body as the garment meets it: its skin's vertices (V, 3) and the rig's bone heads and tails (B, 3)."""

    vertices: np.ndarray
    heads: np.ndarray
    tails: np.ndarray

    @classmethod
    def standing(cls, body: Body) -> Posture:
        return cls(np.asarray(body.vertices, dtype=float), body.rig.heads, body.rig.tails)


@dataclass(frozen=True, eq=False)
class Placement:
    """Where a garment lies on a posture: its levels, stations, the stations' and levels' arc lengths (m),
    the sections' tape girths (M,) (m) and hull radii (M, N) (m)."""

    levels: list[Level]
    stations: Stations
    arc: np.ndarray
    level_arc: np.ndarray
    girths: np.ndarray
    radii: np.ndarray


def place(body: Body, spec: GarmentSpec, posture: Posture, carried: Stations | None = None) -> Placement:
    """The garment's levels and stations on the body in `posture`, with the body's sections there;
    carried: a dressed garment's stations, carried into this posture (as many, the first one's in-plane
    direction turned into its new plane)."""
    posed = JointSet(body.rig.names, posture.heads)
    levels = segment_levels(body, posture.vertices, posed, spec.levels)
    count, first_u = (None, None) if carried is None else (len(carried.origins), carried.u[0])
    stations, arc, level_arc = stations_along(levels, SPACING, count=count, first_u=first_u)
    girths, radii = section_hulls(posture.vertices, body.faces, stations, station_skin(levels, arc, level_arc),
                                  spec.per_ring)
    return Placement(levels, stations, arc, level_arc, girths, radii)


def prepare(body: Body, spec: GarmentSpec) -> tuple[list[Level], Tube, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The levels, the garment's tube and its start rings (V, 3) on the standing body, stations' and levels'
    arc lengths, the sections' hull radii (M, N); every check of the garment against the body is here, before any long work."""
    at = place(body, spec, Posture.standing(body))
    relaxed = relaxed_at_stations(spec, at.girths, at.arc, at.level_arc)
    # a mesh garment's wale at rest is its own length laid along the segment
    wale_ease = 0.0 if spec.mesh is None else spec.mesh.length / float(at.arc[-1]) - 1.0
    tube = build_tube(at.stations, spec.per_ring, relaxed, spec.course, spec.wale, spec.shear, wale_ease)
    return at.levels, tube, body_rings(at.radii, at.stations).reshape(-1, 3), at.arc, at.level_arc, at.radii


def dress(body: Body, spec: GarmentSpec, soft: bool = True, materials: Materials | None = None) -> Dressing:
    """The garment on the standing body, solved (see the module note): on the limb's soft tissue when
    `soft` and the garment is on a limb (`materials`: the tissue's, default the shipped file), else on
    the rigid skin."""
    levels, tube, start, arc, level_arc, radii = prepare(body, spec)
    tissue = limb_tissue(body, spec.segment, tube.stations, radii, materials) \
        if soft and spec.segment in LIMB_BONES else None
    return solve(body, spec, Posture.standing(body), levels, arc, level_arc, radii, tube, tissue, start)


def solve(body: Body, spec: GarmentSpec, posture: Posture, levels: list[Level], arc: np.ndarray,
          level_arc: np.ndarray, radii: np.ndarray, tube: Tube, tissue: LimbTissue | None, start: np.ndarray,
          stiffness: float | None = None, tissue_start: np.ndarray | None = None) -> Dressing:
    """The garment from `start` (V, 3) on the body in `posture` (its sections' hull radii `radii`; its skin rigid, or the limb's `tissue`
    from its nodes `tissue_start`, default at rest): settled on the body held still first, then with the
    tissue. The barrier's κ: `stiffness` (a dressed garment's, `start` its last equilibrium carried into the
    posture), else from the garment's forces at the start; raised on the way where contacts keep closing,
    the answer settled back at it (`equilibrium.settle`)."""
    rest = np.asarray(posture.vertices, dtype=float)
    near = cKDTree(start).query(rest, distance_upper_bound=REACH)[0] <= REACH
    faces = body.faces[near[body.faces].any(axis=1)]
    sub = np.unique(faces)
    local = np.full(len(rest), -1)
    local[sub] = np.arange(len(sub))
    sub_faces = local[faces]
    # first the garment on the body held still (the skin, or the tissue at its start), then on a limb the
    # garment and the tissue solved together from there
    held = ContactBody(rest[sub], sub_faces) if tissue is None else \
        ContactBody(tissue.body.points if tissue_start is None else tissue_start, tissue.body.faces)
    reader = LevelReader.build(tube, arc, level_arc, tissue)
    try:
        # on a limb the held solve is only the coupled one's start: κ is raised there only where CCD blocks a
        # step (not where contacts merely close: each contact would start further out, to be settled back),
        # and carried into the coupled solve, whose answer is settled at the start's κ
        eq = settle(tube, start, held, stiffness=stiffness, reader=reader,
                    answer_stiffness=None if tissue is None else np.inf, adaptive=tissue is None)
    except HitogataError as err:
        raise HitogataError(f"{spec.source}: the garment's start crosses the body ({err}); allowed a garment "
                            "whose segment is clear of other skin") from None
    iterations = eq.iterations
    if tissue is not None:
        eq = settle(tube, eq.garment, tissue.body, stiffness=eq.barrier_stiffness, body_start=tissue_start,
                    reader=reader, answer_stiffness=eq.start_stiffness)
        iterations += eq.iterations
    force = np.zeros_like(rest)
    if tissue is None:
        force[sub] = eq.body_force
    else:  # the tissue's contact forces carried to the skin under it
        surface = tissue.body.surface
        force[sub] = spread_on_surface(rest[sub], sub_faces, tissue.body.points[surface], eq.body_force[surface])
    friction = np.zeros_like(rest)
    friction[sub] = spread_on_surface(rest[sub], sub_faces, eq.garment, -eq.held)
    contact = np.zeros(len(rest), dtype=bool)
    contact[sub] = True
    return Dressing(body, spec, levels, level_arc, arc, tube, eq.garment, eq.garment_force, rest, force, friction, contact,
                    iterations, eq.converged, eq.min_distance, tissue, None if tissue is None else eq.body,
                    eq.barrier_stiffness, radii)


def spread_on_surface(skin: np.ndarray, faces: np.ndarray, points: np.ndarray, forces: np.ndarray) -> np.ndarray:
    """(S, 3) N on the skin's nodes: forces (P, 3) acting at points (P, 3) near the skin, each spread over
    its nearest skin triangle's corners by barycentric weights (their sum kept). The force holding each
    garment vertex in its plane is taken by the skin under it this way (friction: the garment pulls the
    skin the other way), so the garment's loads on the body sum to zero."""
    near = SurfaceQuery(skin, faces).closest(points)
    out = np.zeros_like(skin)
    for corner in range(3):
        np.add.at(out, faces[near.face, corner], near.bary[:, corner:corner + 1] * forces)
    return out
