"""Bodies whose answers are known, to check the garment's contact against: rigid cylinders and
ellipses, and a soft thick-walled cylinder round a rigid core (Lamé's solution).

Used by the tests and the documentation's verification figures; nothing in the pipeline imports this.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from hitogata.fem.assembly import stiffness_matrix
from hitogata.fem.materials import lame
from hitogata.garment.contact.equilibrium import ContactBody
from hitogata.garment.contact.tissue import annulus_tets
from hitogata.garment.contact.tube import Stations, ring_faces
from hitogata.geometry.tets import boundary_faces


def straight_stations(length: float, rings: int) -> Stations:
    """Planes z = const from 0 to `length` (m), basis x, y: a tube along the z axis."""
    z = np.linspace(0.0, length, rings)
    origins = np.stack([np.zeros(rings), np.zeros(rings), z], axis=1)
    return Stations(origins, np.tile([1.0, 0.0, 0.0], (rings, 1)), np.tile([0.0, 1.0, 0.0], (rings, 1)))


def elliptic_rings(stations: Stations, a: float, b: float, per_ring: int, phase: float = 0.0) -> np.ndarray:
    """(M·N, 3) points on an ellipse of semi-axes a (along u) and b (along v) at each station, anticlockwise."""
    t = 2 * np.pi * (np.arange(per_ring) + phase) / per_ring
    coords = np.stack([a * np.cos(t), b * np.sin(t)], axis=-1)
    return stations.place(np.broadcast_to(coords, (len(stations.origins), per_ring, 2))).reshape(-1, 3)


def elliptic_cylinder(a: float, b: float, length: float, per_ring: int, rings: int) -> ContactBody:
    """A rigid elliptic cylinder (circular for a = b) along z from 0 to `length`, outward triangles."""
    points = elliptic_rings(straight_stations(length, rings), a, b, per_ring)
    return ContactBody(points, ring_faces(rings, per_ring))


def lame_indentation(pressure: float, inner: float, outer: float, E: float, nu: float) -> float:
    """How far (m) an external pressure (Pa) pushes in the outer surface of a thick-walled cylinder held
    at its inner radius, in plane strain: u = A r + B / r with u(inner) = 0 and σ_rr(outer) = −p."""
    lam, mu = (float(v) for v in lame(E, nu))
    a = -pressure / (2 * (lam + mu) + 2 * mu * inner ** 2 / outer ** 2)
    return -a * (outer - inner ** 2 / outer)


def soft_annulus(inner: float, outer: float, length: float, E: float, nu: float, radial: int, around: int,
                 along: int) -> ContactBody:
    """A thick-walled cylinder of linear elastic P1 tets (E Pa, ν), its inner surface held (a rigid core),
    every node held along z (plane strain), its outer surface the contact surface."""
    tets, i, j, k = annulus_tets(radial, around, along)
    r = inner + (outer - inner) * i / radial
    angle = 2 * np.pi * j / around
    nodes = np.stack([r * np.cos(angle), r * np.sin(angle), length * k / along], axis=1)
    stiffness = stiffness_matrix(nodes, tets, E, nu)
    fixed = np.zeros((len(nodes), 3), dtype=bool)
    fixed[:, 2] = True
    fixed[np.isclose(r, inner)] = True
    faces, _ = boundary_faces(tets)
    outside = np.isclose(r, outer)[faces].all(axis=1)
    return ContactBody(nodes, faces[outside], sp.csr_matrix(stiffness), fixed.ravel())
