"""Lines drawn on the skin at rest, measured on any deformed copy of the same surface.

A line is a piece of a planar section of the rest skin (a pen drawn along a
straight edge laid on the body): the crossing points of the plane with the
mesh edges, each kept as its edge and the fraction along it, and the segments
joining them inside the faces they cross. On a posed or deformed surface of
the same topology each point moves with its edge, so the line's length there
is the drawn line's length after the deformation — the skin's stretch along
it. Lines are chosen by a mask on the rest crossing points (a side of the
limb, a band along it) on the loops that go round a given centre.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from hitogata.errors import HitogataError
from hitogata.measure.sections import loops_around, section
from hitogata.geometry.topology import topology


@dataclass(frozen=True)
class SkinLine:
    """Points on mesh edges (vertex a, vertex b, fraction s) and the segments joining them, one per face."""

    a: np.ndarray  # (K,)
    b: np.ndarray  # (K,)
    s: np.ndarray  # (K,)
    segments: np.ndarray  # (S, 2) indices into the K points, each segment inside one face

    @property
    def crossings(self) -> int:
        """How many triangles the line crosses."""
        return len(self.segments)

    def points(self, vertices: np.ndarray) -> np.ndarray:
        """(K, 3) the line's points on a surface with the rest topology."""
        return (1.0 - self.s)[:, None] * vertices[self.a] + self.s[:, None] * vertices[self.b]

    def length(self, vertices: np.ndarray) -> float:
        """The line's length (m) on a surface with the rest topology."""
        p = self.points(vertices)
        return float(np.linalg.norm(p[self.segments[:, 0]] - p[self.segments[:, 1]], axis=1).sum())


def draw_line(
    vertices: np.ndarray,
    faces: np.ndarray,
    origin: np.ndarray,
    normal: np.ndarray,
    keep: Callable[[np.ndarray], np.ndarray],
    centre: np.ndarray | None = None,
) -> SkinLine:
    """The part of the rest section (plane through `origin` with `normal`) whose points `keep` marks,
    on the loops round `centre` (a point in the plane; default `origin`)."""
    topo = topology(faces)
    sec = section(vertices, topo, origin, normal)
    around = loops_around(sec, origin if centre is None else centre, normal)
    chosen = np.isin(sec.loop, around) & keep(sec.points)
    segments = sec.segments[chosen[sec.segments].all(axis=1)]
    if not len(segments):
        raise HitogataError("the line misses the skin: no section segment kept")
    used = np.unique(segments)
    renumber = np.full(len(sec.points), -1)
    renumber[used] = np.arange(len(used))
    a, b = topo.edges[sec.edges[used], 0], topo.edges[sec.edges[used], 1]
    span = vertices[b] - vertices[a]
    s = np.einsum("ij,ij->i", sec.points[used] - vertices[a], span) / np.einsum("ij,ij->i", span, span)
    return SkinLine(a, b, s, renumber[segments])
