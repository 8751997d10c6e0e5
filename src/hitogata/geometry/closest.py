"""The closest point of a triangle surface: exact point–triangle closest points, the nearest of a
point's candidate triangles (given in groups, or those whose centroids a k-d tree finds nearest: the true
nearest on meshes of reasonably shaped triangles such as the body's) and barycentric weights on a triangle.

The one place for these; the surface queries of the volume mesher (`volume.surface.SurfaceIndex`),
the scan fit (`fit.closest`), the landmarks (`measure.surface_points`), the skin's contact and slide, and the
tissue mapping (`elastic.mapping`) call them.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy.spatial import cKDTree

# Pairs (query, triangle) evaluated at once: bounds the temporaries to ~100 MB.
PAIRS_AT_ONCE = 1 << 20


def closest_points_on_triangles(p: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Closest point of triangle (a[k], b[k], c[k]) to p[k], all (K, 3) (Ericson 2005, §5.1.5): each pair's
    Voronoi region first, then its point from that region's formula alone."""
    ab, ac = b - a, c - a
    ap, bp, cp = p - a, p - b, p - c
    d1, d2 = np.einsum("ij,ij->i", ab, ap), np.einsum("ij,ij->i", ac, ap)
    d3, d4 = np.einsum("ij,ij->i", ab, bp), np.einsum("ij,ij->i", ac, bp)
    d5, d6 = np.einsum("ij,ij->i", ab, cp), np.einsum("ij,ij->i", ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    # in Ericson's order, the first that holds: vertex A, vertex B, edge AB, vertex C, edge AC, edge BC; else inside
    region = np.select([(d1 <= 0) & (d2 <= 0), (d3 >= 0) & (d4 <= d3), (vc <= 0) & (d1 >= 0) & (d3 <= 0),
                        (d6 >= 0) & (d5 <= d6), (vb <= 0) & (d2 >= 0) & (d6 <= 0),
                        (va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0)], np.arange(6), 6)
    q = np.empty_like(p)
    with np.errstate(divide="ignore", invalid="ignore"):  # a degenerate triangle gives NaN, as the formula says
        k = np.flatnonzero(region == 6)
        total = va[k] + vb[k] + vc[k]
        q[k] = a[k] + ab[k] * (vb[k] / total)[:, None] + ac[k] * (vc[k] / total)[:, None]
        k = np.flatnonzero(region == 5)
        w = (d4[k] - d3[k]) / ((d4[k] - d3[k]) + (d5[k] - d6[k]))
        q[k] = b[k] + (c[k] - b[k]) * w[:, None]
        k = np.flatnonzero(region == 4)
        q[k] = a[k] + ac[k] * (d2[k] / (d2[k] - d6[k]))[:, None]
        k = np.flatnonzero(region == 2)
        q[k] = a[k] + ab[k] * (d1[k] / (d1[k] - d3[k]))[:, None]
    for corner, point in ((0, a), (1, b), (3, c)):
        k = np.flatnonzero(region == corner)
        q[k] = point[k]
    return q


def nearest_on_triangles(tree: cKDTree, tri: np.ndarray, points: np.ndarray, k: int,
                         admissible: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None
                         ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For each of `points` (P, 3): the distance (P,) to the nearest of the triangles `tri` (T, 3, 3) among the
    k whose centroids (`tree`) are nearest, that triangle's index (P,) and the closest point on it (P, 3).
    `admissible(point_rows, triangles)`, if given, says which candidate pairs may count (a point with none
    gets distance inf).

    >>> tri = np.array([[[0.0, 0, 0], [1, 0, 0], [0, 1, 0]], [[5.0, 0, 0], [6, 0, 0], [5, 1, 0]]])
    >>> d, t, q = nearest_on_triangles(cKDTree(tri.mean(axis=1)), tri, np.array([[0.2, 0.2, 0.5]]), 2)
    >>> float(d[0]), int(t[0]), np.round(q[0], 9).tolist()
    (0.5, 0, [0.2, 0.2, 0.0])
    """
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    k = min(k, len(tri))
    dist, face, closest = np.empty(len(points)), np.empty(len(points), dtype=np.int64), np.empty_like(points)
    step = max(1, PAIRS_AT_ONCE // k)
    for s in range(0, len(points), step):
        p = points[s:s + step]
        _, near = tree.query(p, k=k)
        near = near.reshape(len(p), k)
        t = tri[near.ravel()]
        q = closest_points_on_triangles(np.repeat(p, k, axis=0), t[:, 0], t[:, 1], t[:, 2]).reshape(len(p), k, 3)
        d = np.linalg.norm(q - p[:, None, :], axis=2)
        if admissible is not None:
            d[~admissible(np.repeat(np.arange(s, s + len(p)), k), near.ravel()).reshape(d.shape)] = np.inf
        best = d.argmin(axis=1)
        rows = np.arange(len(p))
        dist[s:s + step], face[s:s + step], closest[s:s + step] = d[rows, best], near[rows, best], q[rows, best]
    return dist, face, closest


def nearest_in_groups(distance: np.ndarray, indptr: np.ndarray) -> np.ndarray:
    """For candidates grouped as CSR rows (`indptr`, no group empty): the index of each group's nearest
    (smallest `distance`), the first of equals; a NaN distance is never the nearest unless all of its
    group's are (then the group's first). The same as a stable sort by (group, distance), in linear time.

    >>> nearest_in_groups(np.array([3.0, 1.0, 1.0, np.nan, 2.0, np.nan]), np.array([0, 3, 5, 6])).tolist()
    [1, 4, 5]
    """
    starts = np.asarray(indptr[:-1])
    group = np.repeat(np.arange(len(starts)), np.diff(indptr))
    least = np.fmin.reduceat(distance, starts)
    at = np.flatnonzero(distance == least[group])  # sorted, and so are their groups
    leading = np.ones(len(at), dtype=bool)
    leading[1:] = group[at[1:]] != group[at[:-1]]
    first = np.array(starts, dtype=np.int64)
    first[group[at[leading]]] = at[leading]
    return first


def barycentric_on_triangles(points: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """(K, 3) barycentric weights of points lying on triangles (K, 3, 3), clipped to the triangle."""
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    v0, v1, v2 = b - a, c - a, points - a
    d00, d01, d11 = (v0 * v0).sum(1), (v0 * v1).sum(1), (v1 * v1).sum(1)
    d20, d21 = (v2 * v0).sum(1), (v2 * v1).sum(1)
    den = np.maximum(d00 * d11 - d01 * d01, 1e-300)
    v = (d11 * d20 - d01 * d21) / den
    w = (d00 * d21 - d01 * d20) / den
    bary = np.clip(np.stack([1.0 - v - w, v, w], axis=1), 0.0, 1.0)
    return bary / bary.sum(axis=1, keepdims=True)
