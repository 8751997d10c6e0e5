"""A tubular garment put on the body: the contact pressure of the fabric on the real skin.

The garment starts as rings just outside the standing body's sections along its segment
(`segments.body_rings`) with its relaxed size as sewn, so it is stretched from the start, and Newton
with CCD pulls it onto the skin (`equilibrium.settle`): the loose fit shrunk to its relaxed size. The
skin within `REACH` of the garment's start is the contact surface (both legs' skin where they are near:
the garment never passes into the other limb either). The body is held rigid: the elastic whole body
(`hitogata.elastic`, a 40 mm lattice) answers the garment's loads with indentations of centimetres
(its lower leg is one or two elements thick), so the tissue's answer is left to a model refined under
the garment (docs/garment_contact.md).

The garment's courses stay in their planes (`tube`); the force that holds them there is what friction
on the skin must supply (`hold_on_skin` puts it on the skin, so the garment's loads on the body sum to
zero).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from hitogata.body import Body
from hitogata.errors import HitogataError
from hitogata.garment.contact.equilibrium import ContactBody, Equilibrium, settle
from hitogata.garment.contact.segments import SPACING, Level, body_rings, segment_levels, station_skin, stations_along
from hitogata.garment.contact.spec import GarmentSpec
from hitogata.garment.contact.tube import Tube, build_tube
from hitogata.fit.closest import SurfaceQuery
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


def relaxed_at_stations(spec: GarmentSpec, girths: np.ndarray, arc: np.ndarray, level_arc: np.ndarray) -> np.ndarray:
    """The relaxed circumference (m) at each station: the ease × the body's girth there, or the levels'
    relaxed circumferences interpolated along the segment; refused (one line) where the fabric would be
    stretched beyond the strain its tensile test reached."""
    if spec.relaxed is not None:
        relaxed = np.interp(arc, level_arc, [spec.relaxed[level] for level in spec.levels])
    else:
        relaxed = (1.0 + float(spec.ease or 0.0)) * girths
    strain = girths / relaxed - 1.0
    worst = int(np.argmax(strain))
    tested = spec.course.tested_strain
    if strain[worst] > tested:
        level = spec.levels[int(np.argmin(np.abs(level_arc - arc[worst])))]
        value = f"{100 * relaxed[worst]:.1f} cm" if spec.relaxed is not None else f"{100 * (spec.ease or 0):+.0f}%"
        raise HitogataError(f"{spec.where(level)}: {value} is smaller than the fabric can stretch to near the "
                            f"{level} ({100 * girths[worst]:.1f} cm round: {100 * strain[worst]:.0f} % strain); "
                            f"allowed at least {100 * girths[worst] / (1 + tested):.1f} cm there (the fabric's "
                            f"test reaches {100 * tested:.0f} %)")
    return relaxed


def prepare(body: Body, spec: GarmentSpec) -> tuple[list[Level], Tube, np.ndarray, np.ndarray, np.ndarray]:
    """The levels, the garment's tube and its start rings (V, 3) on the standing body, stations' and levels'
    arc lengths; every check of the garment against the body is here, before any long work."""
    posed = JointSet(body.rig.names, body.rig.heads)
    levels = segment_levels(body, body.vertices, posed, spec.levels)
    stations, arc, level_arc = stations_along(levels, SPACING)
    girths, rings = body_rings(body.vertices, body.faces, stations, station_skin(levels, arc, level_arc), spec.per_ring)
    relaxed = relaxed_at_stations(spec, girths, arc, level_arc)
    tube = build_tube(stations, spec.per_ring, relaxed, spec.course, spec.wale, spec.shear)
    return levels, tube, rings.reshape(-1, 3), arc, level_arc


def dress(body: Body, spec: GarmentSpec) -> Dressing:
    """The garment on the standing body, solved (see the module note)."""
    levels, tube, start, arc, level_arc = prepare(body, spec)
    rest = np.asarray(body.vertices, dtype=float)
    near = cKDTree(start).query(rest, distance_upper_bound=REACH)[0] <= REACH
    faces = body.faces[near[body.faces].any(axis=1)]
    sub = np.unique(faces)
    local = np.full(len(rest), -1)
    local[sub] = np.arange(len(sub))
    sub_faces = local[faces]
    try:
        eq = settle(tube, start, ContactBody(rest[sub], sub_faces))
    except HitogataError as err:
        raise HitogataError(f"{spec.source}: the garment's start crosses the body ({err}); allowed a garment "
                            "whose segment is clear of other skin") from None
    force = np.zeros_like(rest)
    force[sub] = eq.body_force
    friction = np.zeros_like(rest)
    friction[sub] = hold_on_skin(eq, rest[sub], sub_faces)
    contact = np.zeros(len(rest), dtype=bool)
    contact[sub] = True
    return Dressing(body, spec, levels, level_arc, arc, tube, eq.garment, eq.garment_force, rest, force, friction, contact,
                    eq.iterations, eq.converged, eq.min_distance)


def hold_on_skin(eq: Equilibrium, skin: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(S, 3) N on the contact surface's nodes: the force that holds each garment vertex in its plane, taken
    by the skin under it (friction: the garment pulls the skin the other way), spread over the nearest skin
    triangle's corners by barycentric weights. With it the garment's loads on the body sum to zero."""
    near = SurfaceQuery(skin, faces).closest(eq.garment)
    out = np.zeros_like(skin)
    for corner in range(3):
        np.add.at(out, faces[near.face, corner], -near.bary[:, corner:corner + 1] * eq.held)
    return out
