"""Solids to be meshed, described by what the lattice mesher asks of them.

A domain answers two questions: is a point inside, and where does a segment
from an inside point to an outside point leave it (fraction t from the inside
end, and which *part* of the boundary it crosses). A closed triangle surface,
a half-space and any implicit function f < 0 are domains; their intersection
is one too, which is how the trunk is cut from the body (skin ∩ below the
neck ∩ above the hips ∩ not an arm).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from hitogata.volume.surface import SurfaceIndex

# Bisection steps for implicit boundaries: 2^-40 of an edge, far below round-off in metres.
_BISECTION_STEPS = 40


class Domain(Protocol):
    """What the mesher needs of a solid."""

    @property
    def parts(self) -> tuple[str, ...]:
        """Names of the boundary pieces; `exit` reports indices into this."""

    def contains(self, points: np.ndarray) -> np.ndarray:
        """Boolean (P,): inside."""

    def exit(self, inner: np.ndarray, outer: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """For segments inner (inside) → outer (outside): fraction t in (0, 1) where they first
        leave the domain, and the index of the boundary part crossed there."""


class SurfaceDomain:
    """The inside of a closed, outward-oriented triangle surface."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray, name: str = "skin", cell: float | None = None) -> None:
        self.index = SurfaceIndex(vertices, faces, cell)
        self.parts = (name,)

    def contains(self, points: np.ndarray) -> np.ndarray:
        return self.index.contains(points)

    def exit(self, inner: np.ndarray, outer: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        t = self.index.first_crossing(inner, outer)
        # A crossing missed by round-off (the segment grazes an edge): fall back to the midpoint.
        t = np.where(np.isfinite(t), t, 0.5)
        return t, np.zeros(len(t), dtype=np.int64)


@dataclass(frozen=True)
class HalfSpace:
    """Points p with (p − point)·normal < 0: the side the normal points away from."""

    point: np.ndarray
    normal: np.ndarray
    name: str = "cut"

    @property
    def parts(self) -> tuple[str, ...]:
        return (self.name,)

    def contains(self, points: np.ndarray) -> np.ndarray:
        return (np.asarray(points) - self.point) @ self.normal < 0

    def exit(self, inner: np.ndarray, outer: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        a = (inner - self.point) @ self.normal
        b = (outer - self.point) @ self.normal
        return np.clip(a / (a - b), 0.0, 1.0), np.zeros(len(a), dtype=np.int64)


@dataclass(frozen=True)
class ImplicitDomain:
    """Points where a continuous function is negative; boundaries found by bisection."""

    function: Callable[[np.ndarray], np.ndarray]
    name: str = "implicit"

    @property
    def parts(self) -> tuple[str, ...]:
        return (self.name,)

    def contains(self, points: np.ndarray) -> np.ndarray:
        return self.function(np.asarray(points, dtype=np.float64)) < 0

    def exit(self, inner: np.ndarray, outer: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        lo, hi = np.zeros(len(inner)), np.ones(len(inner))
        for _ in range(_BISECTION_STEPS):
            mid = 0.5 * (lo + hi)
            inside = self.function(inner + (outer - inner) * mid[:, None]) < 0
            lo, hi = np.where(inside, mid, lo), np.where(inside, hi, mid)
        return 0.5 * (lo + hi), np.zeros(len(inner), dtype=np.int64)


class Intersection:
    """Points inside every member; boundary parts are the members' parts, in order."""

    def __init__(self, *members: Domain) -> None:
        self.members = members
        self.parts = tuple(name for m in members for name in m.parts)
        self._offsets = np.cumsum([0] + [len(m.parts) for m in members])

    def contains(self, points: np.ndarray) -> np.ndarray:
        inside = np.ones(len(points), dtype=bool)
        for member in self.members:
            inside[inside] = member.contains(points[inside])
        return inside

    def exit(self, inner: np.ndarray, outer: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        t = np.full(len(inner), np.inf)
        part = np.full(len(inner), -1, dtype=np.int64)
        for member, offset in zip(self.members, self._offsets):
            leaves = ~member.contains(outer)
            if not leaves.any():
                continue
            tm, pm = member.exit(inner[leaves], outer[leaves])
            earlier = tm < t[leaves]
            rows = np.flatnonzero(leaves)[earlier]
            t[rows], part[rows] = tm[earlier], pm[earlier] + offset
        return t, part
