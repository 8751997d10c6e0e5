"""The broad phase: every pair of overlapping axis-aligned boxes, the one place for it (the
self-intersection tests of `mesh_checks` and `integrity`, the offset limit). The barrier's own pairs are
the IPC Toolkit's (`ipctk`), found inside its collision set.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

SPARSE_ACTIVE = 0.25  # with fewer active boxes than this share, only theirs are looked up


def box_pairs(lo: np.ndarray, hi: np.ndarray, active: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """All pairs (i < j) of overlapping boxes [lo, hi] (B, 3); with `active` (B,) bool, only
    pairs with at least one active box.

    Boxes are sorted into size classes (powers of two of their largest side),
    one k-d tree of centres per class; each pair of classes is searched in the
    Chebyshev metric within the sum of their largest half-sides, so a box meets
    only boxes near it, never a whole crowded cell of tiny ones. With few
    active boxes only theirs are looked up (a tree of the active ones per
    class against each class's whole tree): the cost goes with the active.
    """
    centre, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    size = np.maximum(half.max(axis=1), 1e-12)
    level = np.floor(np.log2(size / size.min())).astype(np.int64)
    active = np.ones(len(lo), dtype=bool) if active is None else np.asarray(active, dtype=bool)
    classes = [np.flatnonzero(level == c) for c in np.unique(level)]
    trees = [cKDTree(centre[m]) for m in classes]
    largest = [float(size[m].max()) for m in classes]
    sparse = bool(active.mean() < SPARSE_ACTIVE)
    movers = [m[active[m]] for m in classes]
    mover_trees = [cKDTree(centre[m]) if sparse and len(m) else None for m in movers]
    lo_axes, hi_axes = np.ascontiguousarray(lo.T), np.ascontiguousarray(hi.T)
    found_i, found_j = [np.zeros(0, dtype=np.intp)], [np.zeros(0, dtype=np.intp)]
    for a, (ma, ta) in enumerate(zip(classes, trees)):
        for b in range(a, len(classes)):
            mb = classes[b]
            if not (len(movers[a]) or len(movers[b])):
                continue
            reach = largest[a] + largest[b]
            if sparse:
                i, j = _mover_hits(movers, mover_trees, classes, trees, a, b, reach)
            elif a == b:
                hits = ta.query_pairs(reach, p=np.inf, output_type="ndarray")
                i, j = ma[hits[:, 0]], ma[hits[:, 1]]
            else:
                hits = ta.sparse_distance_matrix(trees[b], reach, p=np.inf, output_type="ndarray")
                i, j = ma[hits["i"]], mb[hits["j"]]
            keep = active[i] | active[j]
            i, j = i[keep], j[keep]
            for low, high in zip(lo_axes, hi_axes):  # axis by axis, the survivors only (~25 % faster)
                keep = (low[i] <= high[j]) & (low[j] <= high[i])
                i, j = i[keep], j[keep]
            found_i.append(i)
            found_j.append(j)
    i, j = np.concatenate(found_i, dtype=np.intp), np.concatenate(found_j, dtype=np.intp)
    i, j = np.minimum(i, j), np.maximum(i, j)
    if sparse:  # a pair of two active boxes is found from both sides
        unique = np.unique(i.astype(np.int64) * len(lo) + j)
        i, j = (unique // len(lo)).astype(np.intp), (unique % len(lo)).astype(np.intp)
    return i, j


def _mover_hits(movers: list[np.ndarray], mover_trees: list, classes: list[np.ndarray], trees: list,
                a: int, b: int, reach: float) -> tuple[np.ndarray, np.ndarray]:
    """Candidate pairs between classes a and b with an active box: a's active against all of b,
    and (a != b) all of a against b's active; never a box with itself."""
    found_i, found_j = [np.zeros(0, dtype=np.intp)], [np.zeros(0, dtype=np.intp)]
    for one, other in ((a, b), (b, a)) if a != b else ((a, a),):
        if mover_trees[one] is None:
            continue
        hits = mover_trees[one].sparse_distance_matrix(trees[other], reach, p=np.inf, output_type="ndarray")
        i, j = movers[one][hits["i"]], classes[other][hits["j"]]
        found_i.append(i[i != j])
        found_j.append(j[i != j])
    return np.concatenate(found_i, dtype=np.intp), np.concatenate(found_j, dtype=np.intp)
