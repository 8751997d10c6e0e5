"""The closest point of a triangle (`geometry.closest`): each of Ericson's Voronoi regions against a dense
search over the triangle, and the nearest candidate of each group."""

from __future__ import annotations

import numpy as np

from hitogata.geometry.closest import closest_points_on_triangles, nearest_in_groups


def dense_closest(p: np.ndarray, tri: np.ndarray, n: int = 400) -> np.ndarray:
    """The nearest of a fine barycentric lattice of the triangle (n steps a side) to p."""
    i, j = np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij")
    keep = i + j <= n
    u, v = i[keep] / n, j[keep] / n
    points = tri[0] + u[:, None] * (tri[1] - tri[0]) + v[:, None] * (tri[2] - tri[0])
    return points[np.argmin(np.linalg.norm(points - p, axis=1))]


def test_each_region_gives_the_nearest_point_of_the_triangle():
    tri = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.2, 0.8, 0.0]])
    # inside (above the face), beyond each vertex, beyond each edge
    queries = np.array([[0.3, 0.2, 0.5], [-0.5, -0.4, 0.1], [1.6, -0.2, -0.3], [0.1, 1.5, 0.2],
                        [0.5, -0.7, 0.4], [0.9, 0.6, -0.2], [-0.4, 0.5, 0.3]])
    got = closest_points_on_triangles(queries, *[np.repeat(v[None], len(queries), axis=0) for v in tri])
    for q, g in zip(queries, got):
        assert np.linalg.norm(g - dense_closest(q, tri)) < 3e-3, (q, g)  # the lattice's spacing
    assert np.allclose(got[0], [0.3, 0.2, 0.0]) and np.allclose(got[1], tri[0]) and np.allclose(got[2], tri[1])
    assert np.allclose(got[3], tri[2]) and np.allclose(got[4], [0.5, 0.0, 0.0])


def test_random_pairs_are_no_farther_than_any_corner_or_the_dense_search():
    rng = np.random.default_rng(7)
    p, a, b, c = (rng.normal(size=(60, 3)) for _ in range(4))
    got = closest_points_on_triangles(p, a, b, c)
    for k in range(len(p)):
        tri = np.stack([a[k], b[k], c[k]])
        best = np.linalg.norm(dense_closest(p[k], tri, 200) - p[k])
        assert np.linalg.norm(got[k] - p[k]) <= best + 1e-12
        assert np.linalg.norm(got[k] - dense_closest(p[k], tri, 200)) < 0.05 * np.abs(tri).max()


def test_the_nearest_of_each_group_is_a_stable_sorts():
    rng = np.random.default_rng(11)
    sizes = rng.integers(1, 9, size=500)
    indptr = np.concatenate([[0], np.cumsum(sizes)])
    distance = rng.integers(0, 5, size=indptr[-1]).astype(float)  # many ties
    distance[rng.random(len(distance)) < 0.1] = np.nan
    group = np.repeat(np.arange(len(sizes)), sizes)
    order = np.lexsort((distance, group))  # NaN sorts last; equals keep their order
    expected = order[np.searchsorted(group[order], np.arange(len(sizes)))]
    assert np.array_equal(nearest_in_groups(distance, indptr), expected)
