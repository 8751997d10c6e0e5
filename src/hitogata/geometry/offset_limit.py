"""Keep an offset surface whole: hold back an offset field where it would fold or cross the surface.

The elastic skin is the skinned skin plus an offset interpolated from the
finite-element nodes (`BodyDynamics.frame`). At 40 mm the elements cannot
resolve a crease: where the forearm meets the upper arm at 150°, or the
thigh meets the belly, the tissue on the two sides of the crease carries
offsets that push one side's skin through the other's, or fold neighbouring
triangles, where skinning alone does not (the elbow scenario: 10 folded and
89 crossing triangle pairs beyond skinning's at 150°).

`OffsetLimiter` scales the offset down, vertex by vertex, until the surface
`reference + w·offset` has no folded neighbour pair and no crossing
triangle pair that the reference (and the rest surface) has not:

1. broad phase once per call: a triangle at any weights in [0, 1] lies in
   the union of its boxes at weight 0 and 1, so the pairs of overlapping
   union boxes with a face that moves are the only ones that can cross
   (less those crossing in the reference or at rest, which are not this
   offset's doing); the broad phase's cost goes with the faces that move;
2. in rounds: the vertices of every offending pair have their hold raised
   by `OffsetLimitSettings.step` (to 1 at most: offset gone), and the hold
   spreads over the skin around them, fading smoothly to nothing over
   `OffsetLimitSettings.width` along the surface, so the held-back region has no edge of its own.

At hold 1 on all its corners a triangle is where the reference puts it, so
every offending pair has a corner whose hold can still rise: the rounds end.
The weights (V,) say how much of the offset each vertex kept.

`OffsetLimiter.hold_crossings` holds back crossings alone, looked for at each
round's surface among the faces whose weights changed rather than by the swept
boxes: for an offset that is a motion (the contact's hold-back towards a
motion's previous frame), whose swept boxes overlap every box of the part
they move with.
"""

from __future__ import annotations

import copy
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.sparse.csgraph import dijkstra

from hitogata.errors import require, require_above, require_whole
from hitogata.geometry.broad_phase import box_pairs
from hitogata.geometry.integrity import MOVED, _crossing_pairs, _folded, _intersect, _neighbour_pairs, _pair_keys
from hitogata.geometry.mesh_checks import _apart, _faces, edge_graph, self_intersections

ROUNDING = 1e-6  # m: boxes widened by this cover a float32 surface's rounding (float32's, not a choice)
HELD = 1e-4  # m: a vertex whose offset is held back by more is reported as held back (the reports' threshold)


@dataclass(frozen=True)
class OffsetLimitSettings:
    """How the limiter holds an offset back, SI (m). Refused when out of range (`__post_init__`)."""

    step: float = 0.5
    """hold added per round to the corners of an offending pair (0 < step ≤ 1; 1: the offset gone at once)."""
    width: float = 0.04
    """m along the surface: a hold fades to nothing over this (one 40 mm element of the tissue mesh)."""
    max_rounds: int = 64
    """a guard on the rounds, far beyond need (each round lifts a corner; 2-6 rounds are typical)."""

    def __post_init__(self) -> None:
        require_above("OffsetLimitSettings.step", self.step, what="a share")
        require(self.step <= 1, "OffsetLimitSettings.step", self.step, "a share above 0 and at most 1")
        require_above("OffsetLimitSettings.width", self.width, what="a distance (m)")
        require_whole("OffsetLimitSettings.max_rounds", self.max_rounds, 1)


OFFSET_LIMIT_DEFAULTS = OffsetLimitSettings()


class OffsetLimiter:
    """For one surface (rest vertices (V, 3), faces (T, 3)): weights that keep reference + w·offset whole,
    held back as `settings` say."""

    def __init__(self, rest: np.ndarray, faces: np.ndarray, settings: OffsetLimitSettings = OFFSET_LIMIT_DEFAULTS,
                 crossing_at_rest: np.ndarray | None = None) -> None:
        """crossing_at_rest: the surface's `crossing_at_rest` found before (kept with a body's model: a whole
        test of the surface), else found here."""
        self.settings = settings
        self.faces = _faces(faces)
        rest = np.asarray(rest, dtype=np.float64)
        self.pairs = _neighbour_pairs(self.faces)
        self.crossing_at_rest = _pair_keys(_crossing_pairs(rest, self.faces), len(self.faces)) \
            if crossing_at_rest is None else np.asarray(crossing_at_rest, dtype=np.int64)
        self.graph = edge_graph(rest, self.faces)

    def with_settings(self, settings: OffsetLimitSettings) -> OffsetLimiter:
        """This limiter holding back as `settings` say (itself when they are its own): the surface's
        neighbour pairs, rest crossings and edge graph shared, not found again."""
        if settings == self.settings:
            return self
        other = copy.copy(self)
        other.settings = settings
        return other

    def __call__(self, reference: np.ndarray, offset: np.ndarray, ceiling: np.ndarray | None = None,
                 candidates: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """The surface reference + w·offset (V, 3), in the reference's dtype (checked as rounded to it: a
        float32 surface is judged as it will be stored), and w (V,), 1 where nothing folds or crosses;
        ceiling (V,): w never above it (a motion holds and gives back gradually); candidates: this
        reference and offset's `candidates`, if already found."""
        dtype = np.asarray(reference).dtype
        if candidates is None:
            candidates = self.candidates(reference, offset)
        reference = np.asarray(reference, dtype=np.float64)
        folded_in_reference = _folded(reference, self.faces, self.pairs)
        crosses = np.zeros(len(candidates), dtype=bool)

        def offending(x: np.ndarray, changed: np.ndarray) -> np.ndarray:
            retest = changed[candidates].any(axis=1)  # pairs with a face whose weights changed
            crosses[retest] = _intersect(x, self.faces, candidates[retest])
            folded = self.pairs[_folded(x, self.faces, self.pairs) & ~folded_in_reference]
            return np.concatenate([candidates[crosses].ravel(), folded.ravel()])

        return self._hold(reference, offset, ceiling, dtype, offending)

    def hold_crossings(self, reference: np.ndarray, offset: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """As calling the limiter, crossings only (a fold held back towards a reference that crosses nearby
        would bring that crossing back), the crossing pairs found at each round's surface among the faces
        whose weights changed: for an offset that is a motion (a motion's frame to the next, a hand moving
        40 mm), whose swept boxes (`candidates`) overlap every box of the rigid part they move with."""
        dtype = np.asarray(reference).dtype
        reference = np.asarray(reference, dtype=np.float64)
        moving = (np.abs(np.asarray(offset)).max(axis=1) > MOVED)[self.faces].any(axis=1)
        crossing = np.zeros((0, 2), dtype=np.intp)

        def offending(x: np.ndarray, changed: np.ndarray) -> np.ndarray:
            nonlocal crossing
            found = _crossing_pairs(x, self.faces, changed & moving)
            found = found[~np.isin(_pair_keys(found, len(self.faces)), self.crossing_at_rest)]
            found = found[~_intersect(reference, self.faces, found)]  # the reference's own crossings stay
            crossing = np.concatenate([crossing[~changed[crossing].any(axis=1)], found])  # the unchanged still cross
            return crossing.ravel()

        return self._hold(reference, offset, None, dtype, offending)

    def _hold(self, reference: np.ndarray, offset: np.ndarray, ceiling: np.ndarray | None, dtype: np.dtype,
              offending: Callable[[np.ndarray, np.ndarray], np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        """The rounds: the corners of the faces `offending(x, changed)` names at the surface x (given the faces
        whose weights changed since the last round, all at first) have their hold raised, until none is left."""
        offset = np.asarray(offset, dtype=np.float64)
        hold = np.zeros(len(reference))
        top = np.ones(len(reference)) if ceiling is None else np.clip(ceiling, 0.0, 1.0)
        w = top
        changed = np.ones(len(self.faces), dtype=bool)
        for _ in range(self.settings.max_rounds):
            surface = (reference + w[:, None] * offset).astype(dtype)
            corners = np.unique(self.faces[offending(surface.astype(np.float64), changed)])
            corners = corners[hold[corners] < 1.0]
            if not len(corners):
                break
            hold[corners] = np.minimum(hold[corners] + self.settings.step, 1.0)
            previous, w = w, np.minimum(top, 1.0 - self.spread(hold))
            changed = (w != previous)[self.faces].any(axis=1)
        return surface, w

    def candidates(self, reference: np.ndarray, offset: np.ndarray) -> np.ndarray:
        """(K, 2) face pairs that may cross at some weights and do not cross in the reference or at rest."""
        reference = np.asarray(reference, dtype=np.float64)
        offset = np.asarray(offset, dtype=np.float64)
        a, b = reference[self.faces], (reference + offset)[self.faces]
        # widened: the surface is judged rounded to its dtype (float32 moves a vertex ~1e-7 m)
        lo = np.minimum(a.min(axis=1), b.min(axis=1)) - ROUNDING
        hi = np.maximum(a.max(axis=1), b.max(axis=1)) + ROUNDING
        # as surface_integrity: a face whose corners all stay within MOVED of the reference is the reference's
        active = (np.abs(offset).max(axis=1) > MOVED)[self.faces].any(axis=1)
        i, j = box_pairs(lo, hi, active)
        pairs = _apart(self.faces, i, j)
        pairs = pairs[~np.isin(_pair_keys(pairs, len(self.faces)), self.crossing_at_rest)]
        return pairs[~_intersect(reference, self.faces, pairs)]

    def crossings(self, surface: np.ndarray, near: np.ndarray | None = None) -> np.ndarray:
        """(K, 2) the face pairs of `surface` that cross, less those crossing at rest; with `near` (V,) bool,
        only pairs of faces touching it (a whole skin's test takes ten times as long)."""
        kept = np.arange(len(self.faces)) if near is None else np.flatnonzero(near[self.faces].any(axis=1))
        pairs = kept[self_intersections(surface, self.faces[kept])]
        return pairs[~np.isin(_pair_keys(pairs, len(self.faces)), self.crossing_at_rest)]

    def spread(self, hold: np.ndarray) -> np.ndarray:
        """(V,) the holds spread over the surface: each held vertex's hold times a smooth fall to 0 at `settings.width`."""
        out, width = np.zeros_like(hold), self.settings.width
        for level in np.unique(hold[hold > 0]):
            sources = np.flatnonzero(hold == level)
            distance = dijkstra(self.graph, directed=False, indices=sources, limit=width, min_only=True)
            u = np.clip(np.asarray(distance) / width, 0.0, 1.0)
            out = np.maximum(out, level * (1.0 - u * u * (3.0 - 2.0 * u)))
        return out
