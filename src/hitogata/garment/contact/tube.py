"""A tubular garment's mesh: rings of the fabric's courses at stations along a body segment.

The tube is M rings of N vertices, ring j lying in the plane of station j
(its origin and in-plane basis u, v; the axis u × v points along the tube).
Its rest (relaxed, as sewn) shape is a stack of circles whose polygons have
the relaxed circumference C₀ of their station (interpolated between the
garment's levels by the caller) and whose spacing along the axis is the
stations' own (times 1 + the wale's ease): a frustum between rings. Each
triangle's course runs round the ring, its wale along the axis.

The garment's courses stay in their stations' planes: each vertex moves in
its ring's plane only (two unknowns, `in_plane`). A knit's courses are held
round the limb where it was put on — by friction on the skin and by the
wale's tension — and the pressure a stocking is classified by is the one in
that plane; the garment has no friction model, so without this hold a
frictionless tube on a tapered limb would slide to its narrow end.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from hitogata.errors import HitogataError
from hitogata.garment.contact.membrane import Membrane
from hitogata.garment.fabric import Fabric


@dataclass(frozen=True, eq=False)
class Stations:
    """Planes along a segment: origins (M, 3) on its axis, in-plane unit bases u, v (M, 3) each."""

    origins: np.ndarray
    u: np.ndarray
    v: np.ndarray

    @property
    def axis(self) -> np.ndarray:
        """(M, 3) the planes' normals u × v, along the tube."""
        return np.cross(self.u, self.v)

    def place(self, coords: np.ndarray) -> np.ndarray:
        """3D points (M, N, 3) of in-plane coordinates (M, N, 2)."""
        return (self.origins[:, None] + coords[..., :1] * self.u[:, None] + coords[..., 1:] * self.v[:, None])

    def coordinates(self, points: np.ndarray) -> np.ndarray:
        """In-plane coordinates (M, N, 2) of points (M, N, 3) (projected onto each ring's plane)."""
        d = points - self.origins[:, None]
        return np.stack([np.einsum("mni,mi->mn", d, self.u), np.einsum("mni,mi->mn", d, self.v)], axis=-1)


def ring_faces(n_rings: int, per_ring: int) -> np.ndarray:
    """(2 N (M − 1), 3) triangles between consecutive rings, vertex j·N + i, outward when rings run
    anticlockwise round the axis: first those with an edge (corners 0 → 1) on the lower ring, then those
    with an edge (corners 2 → 1) on the upper one."""
    i = np.arange(per_ring)
    j = np.arange(n_rings - 1)[:, None]
    a, b = j * per_ring + i, j * per_ring + (i + 1) % per_ring
    c, d = a + per_ring, b + per_ring
    return np.concatenate([np.stack([a, b, d], -1).reshape(-1, 3), np.stack([a, d, c], -1).reshape(-1, 3)])


def polygon_radius(circumference: np.ndarray | float, per_ring: int) -> np.ndarray:
    """Radius of the regular N-gon with this perimeter."""
    return np.asarray(circumference, dtype=float) / (2.0 * per_ring * np.sin(np.pi / per_ring))


@dataclass(frozen=True, eq=False)
class Tube:
    """A tubular garment on its stations: faces, the membrane of its rest shape, rings (M, N)."""

    stations: Stations
    per_ring: int
    faces: np.ndarray
    membrane: Membrane
    relaxed: np.ndarray  # (M,) m, the relaxed circumference of each ring

    @property
    def n_rings(self) -> int:
        return len(self.stations.origins)

    def in_plane(self) -> sp.csr_matrix:
        """J (3 V × 2 V): the positions' change for a change of the in-plane coordinates (vertex-major)."""
        m, n = self.n_rings, self.per_ring
        basis = np.stack([np.repeat(self.stations.u, n, axis=0), np.repeat(self.stations.v, n, axis=0)], axis=2)
        rows = np.repeat(np.arange(3 * m * n), 2)
        cols = (2 * np.arange(m * n)[:, None, None] + np.arange(2)[None, None, :]).repeat(3, axis=1).ravel()
        return sp.csr_matrix((basis.ravel(), (rows, cols)), shape=(3 * m * n, 2 * m * n))

    def ring_strains(self, x: np.ndarray) -> np.ndarray:
        """The course strain of each ring (M,): its polygon's length over its relaxed circumference, − 1."""
        rings = x.reshape(self.n_rings, self.per_ring, 3)
        length = np.linalg.norm(np.roll(rings, -1, axis=1) - rings, axis=2).sum(axis=1)
        return length / self.relaxed - 1.0


def build_tube(stations: Stations, per_ring: int, relaxed: np.ndarray, course: Fabric, wale: Fabric,
               shear: float, wale_ease: float = 0.0) -> Tube:
    """The tube whose ring j has relaxed circumference relaxed[j] (m) and whose rest spacing along the
    axis is the stations' spacing × (1 + wale_ease)."""
    relaxed = np.asarray(relaxed, dtype=float)
    if per_ring < 8:
        raise HitogataError(f"garment: {per_ring} vertices round a ring; allowed 8 or more")
    if len(relaxed) != len(stations.origins) or len(relaxed) < 2:
        raise HitogataError("garment: one relaxed circumference per station, at least two stations")
    bad = ~(np.isfinite(relaxed) & (relaxed > 0))
    if bad.any():
        raise HitogataError(f"garment: relaxed circumference {relaxed[bad][0]!r} m; allowed > 0")
    spacing = np.linalg.norm(np.diff(stations.origins, axis=0), axis=1) * (1.0 + wale_ease)
    heights = np.concatenate([[0.0], np.cumsum(spacing)])
    angle = 2 * np.pi * np.arange(per_ring) / per_ring
    radius = polygon_radius(relaxed, per_ring)
    rest = np.stack([radius[:, None] * np.cos(angle), radius[:, None] * np.sin(angle),
                     np.broadcast_to(heights[:, None], (len(relaxed), per_ring))], axis=-1).reshape(-1, 3)
    faces = ring_faces(len(relaxed), per_ring)
    # the course runs along each triangle's edge on a ring (its chord): a uniformly stretched ring then
    # stretches every course by its polygon's strain
    half = len(faces) // 2
    course_direction = np.concatenate([rest[faces[:half, 1]] - rest[faces[:half, 0]],
                                       rest[faces[half:, 1]] - rest[faces[half:, 2]]])
    membrane = Membrane.build(rest, faces, course_direction, course, wale, shear)
    return Tube(stations, per_ring, faces, membrane, relaxed)
