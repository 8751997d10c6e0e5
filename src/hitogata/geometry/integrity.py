"""Is a moving surface still whole? Per-frame checks of a deformed triangle mesh against its rest shape.

`surface_integrity(rest, faces, frames)` looks at every frame of a motion of
one surface (same faces throughout) and counts what a tear or a crumple
leaves behind:

- newly folded neighbour pairs: two triangles sharing an edge whose normals
  turn more than `FOLD_ANGLE` (120°) apart, where they did not at rest;
- new self-intersections: pairs of triangles (sharing no vertex) that cross
  in the frame but not at rest (with a reference: pairs with a triangle off
  its reference position; the others are the reference's own);
- the largest vertex speed (frame to frame, m/s) and vertices below the floor;
- given a reference motion of the same surface (e.g. the skin by skinning
  alone at the same poses): the largest displacement from it, its largest
  change from one frame to the next (a jump of the deformation itself, as
  opposed to the skeleton's own motion), and which folds and crossings the
  reference does not have at the same pose too.

The self-intersection broad phase runs per frame over size classes of the
triangles' bounding boxes (a k-d tree per class, Chebyshev metric), so the
tiny triangles of the face and hands and the large ones of the trunk each
meet only their own neighbourhood: about 0.3 s a frame for the 24k-triangle
body, under two thirds of one uniform grid's time, less with a reference
(only triangles off it count). The exact narrow phase is
`mesh_checks`' triangle–triangle test.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.geometry.broad_phase import SPARSE_ACTIVE, box_pairs
from hitogata.geometry.mesh_checks import _PLANE_TOLERANCE, _apart, _faces, _triangles_intersect
from hitogata.geometry.normals import triangle_normals

FOLD_ANGLE = 120.0  # degrees between neighbouring triangles' normals: a fold, not a bend
FLOOR_TOLERANCE = 1e-3  # m: a vertex lower than the floor by more than this is below it
# m: a vertex this close to its reference position is where the reference has it (a fifth of a
# millimetre, far below the 40 mm tissue mesh's resolution; crossings of triangles that all stay
# this close are the reference's own, and the broad phase looks up only the triangles that move)
MOVED = 2e-4


@dataclass(frozen=True)
class SurfaceIntegrity:
    """Per-frame figures (arrays of length F) of a moving surface; lengths m, speeds m/s."""

    times: np.ndarray
    new_folds: np.ndarray  # neighbour pairs folded beyond FOLD_ANGLE, not folded at rest
    new_intersections: np.ndarray  # crossing triangle pairs not crossing at rest
    speed: np.ndarray  # largest vertex speed from the previous frame (0 in the first)
    below_floor: np.ndarray  # vertices below floor − FLOOR_TOLERANCE
    lowest: np.ndarray  # lowest vertex height
    # against the reference motion (zeros without one):
    folds_beyond_reference: np.ndarray  # new folds the reference has not at the same frame
    below_floor_beyond_reference: np.ndarray  # vertices below the floor whose reference position is not
    intersections_beyond_reference: np.ndarray  # new crossings the reference has not at the same frame
    displacement: np.ndarray  # largest distance of a vertex from its reference position
    jump: np.ndarray  # largest change of a vertex's displacement from the previous frame
    jump_speed: np.ndarray  # the same per second

    def worst(self) -> dict:
        """The run's headline figures: maxima over frames and when they happen (SI)."""
        def at(values: np.ndarray) -> float:
            return float(self.times[int(np.argmax(values))])

        return {
            "new_folds": int(self.new_folds.max()), "new_folds_time_s": at(self.new_folds),
            "folds_beyond_skinning": int(self.folds_beyond_reference.max()),
            "new_self_intersections": int(self.new_intersections.max()),
            "new_self_intersections_time_s": at(self.new_intersections),
            "self_intersections_beyond_skinning": int(self.intersections_beyond_reference.max()),
            "largest_speed_m_s": float(self.speed.max()), "largest_speed_time_s": at(self.speed),
            "below_floor": int(self.below_floor.max()), "lowest_m": float(self.lowest.min()),
            "below_floor_beyond_skinning": int(self.below_floor_beyond_reference.max()),
            "largest_elastic_m": float(self.displacement.max()), "largest_elastic_time_s": at(self.displacement),
            "largest_elastic_jump_m": float(self.jump.max()),
            "largest_elastic_jump_speed_m_s": float(self.jump_speed.max()),
            "largest_elastic_jump_time_s": at(self.jump),
        }


def surface_integrity(rest: np.ndarray, faces: np.ndarray, frames: np.ndarray, times: np.ndarray | None = None,
                      reference: np.ndarray | None = None, floor: float = 0.0) -> SurfaceIntegrity:
    """Check every frame (F, V, 3) of a surface (faces (T, 3)) against its rest shape (V, 3).

    times (F,) s: default one frame per second; reference (F, V, 3): the same
    surface moved another way (skinning alone), whose folds and crossings at
    the same frame are not counted in the `..._beyond_reference` figures;
    floor: the floor's height (y up).
    """
    faces = _faces(faces)
    rest = np.asarray(rest, dtype=np.float64)
    frames = np.asarray(frames)
    n = len(frames)
    times = np.arange(n, dtype=float) if times is None else np.asarray(times, dtype=float)
    pairs = _neighbour_pairs(faces)
    folded_at_rest = _folded(rest, faces, pairs)
    crossing_at_rest = _pair_keys(_crossing_pairs(rest, faces), len(faces))
    out = {k: np.zeros(n, dtype=int) for k in ("new_folds", "new_intersections", "below_floor",
                                               "folds_beyond_reference", "intersections_beyond_reference",
                                               "below_floor_beyond_reference")}
    out.update({k: np.zeros(n) for k in ("speed", "lowest", "displacement", "jump", "jump_speed")})
    previous = previous_offset = None
    for k in range(n):
        x = frames[k].astype(np.float64)
        folds = _folded(x, faces, pairs) & ~folded_at_rest
        r = None if reference is None else np.asarray(reference[k], dtype=np.float64)
        # With a reference, pairs of faces where the frame is the reference are the reference's own.
        moved = None if r is None else (np.abs(x - r).max(axis=1) > MOVED)[faces].any(axis=1)
        crossing = _crossing_pairs(x, faces, moved)
        new = crossing[~np.isin(_pair_keys(crossing, len(faces)), crossing_at_rest)]
        out["new_folds"][k], out["new_intersections"][k] = int(folds.sum()), len(new)
        low = x[:, 1] < floor - FLOOR_TOLERANCE
        out["below_floor"][k] = int(low.sum())
        out["lowest"][k] = float(x[:, 1].min())
        if previous is not None:
            dt = times[k] - times[k - 1]
            out["speed"][k] = float(np.linalg.norm(x - previous, axis=1).max() / dt) if dt > 0 else np.inf
        if r is not None:
            out["folds_beyond_reference"][k] = int((folds & ~_folded(r, faces, pairs)).sum())
            out["intersections_beyond_reference"][k] = int((~_intersect(r, faces, new)).sum())
            out["below_floor_beyond_reference"][k] = int((low & (r[:, 1] >= floor - FLOOR_TOLERANCE)).sum())
            offset = x - r
            out["displacement"][k] = float(np.linalg.norm(offset, axis=1).max())
            if previous_offset is not None:
                out["jump"][k] = float(np.linalg.norm(offset - previous_offset, axis=1).max())
                dt = times[k] - times[k - 1]
                out["jump_speed"][k] = out["jump"][k] / dt if dt > 0 else np.inf
            previous_offset = offset
        else:
            out["folds_beyond_reference"][k], out["intersections_beyond_reference"][k] = folds.sum(), len(new)
            out["below_floor_beyond_reference"][k] = out["below_floor"][k]
        previous = x
    return SurfaceIntegrity(times=times, **out)


def _neighbour_pairs(faces: np.ndarray) -> np.ndarray:
    """(E, 2) faces sharing an edge (each interior edge of a manifold once)."""
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    owner = np.tile(np.arange(len(faces)), 3)
    order = np.lexsort((edges[:, 1], edges[:, 0]))
    e, o = edges[order], owner[order]
    same = np.flatnonzero(np.all(e[1:] == e[:-1], axis=1))
    return np.stack([o[same], o[same + 1]], axis=1)


def _folded(x: np.ndarray, faces: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    """(E,) bool: the pair's normals turn more than FOLD_ANGLE apart."""
    tri = x[faces]
    normal = triangle_normals(tri)
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
    cos = np.einsum("ij,ij->i", normal[pairs[:, 0]], normal[pairs[:, 1]])
    return cos < np.cos(np.radians(FOLD_ANGLE))


def _pair_keys(pairs: np.ndarray, n: int) -> np.ndarray:
    return pairs[:, 0].astype(np.int64) * n + pairs[:, 1]


def _intersect(x: np.ndarray, faces: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    """(K,) bool: the triangle pairs cross at positions x."""
    if not len(pairs):
        return np.zeros(0, dtype=bool)
    size = float(np.linalg.norm(x.max(axis=0) - x.min(axis=0)))
    return _triangles_intersect(x[faces[pairs[:, 0]]], x[faces[pairs[:, 1]]], _PLANE_TOLERANCE * size)


def _crossing_pairs(x: np.ndarray, faces: np.ndarray, active: np.ndarray | None = None) -> np.ndarray:
    """(K, 2) sorted face pairs (i < j, sharing no vertex) whose triangles intersect (with
    `active` (T,) bool: only pairs with an active face)."""
    near = np.arange(len(faces))
    if active is not None and active.mean() < SPARSE_ACTIVE and active.any():
        # a few active faces (a limiter's round): only the faces reaching into their bounds can meet one,
        # those with no side of the bounds (below or above along an axis: a bit each) all three corners lie on
        corners = x[faces[active]].reshape(-1, 3)
        sides = np.packbits(np.hstack([x < corners.min(axis=0), x > corners.max(axis=0)]), axis=1,
                            bitorder="little")[:, 0]
        near = np.flatnonzero((sides[faces[:, 0]] & sides[faces[:, 1]] & sides[faces[:, 2]]) == 0)
        active = active[near]
    tri = x[faces[near]]
    i, j = box_pairs(tri.min(axis=1), tri.max(axis=1), active)
    pairs = _apart(faces, near[i], near[j])
    return pairs[_intersect(x, faces, pairs)]
