"""From nodal displacements to the body's skin vertices: a sparse interpolation matrix.

Each skin vertex is located in the tet that contains it and weighted by that
tet's shape functions there (barycentric for P1, quadratic for P2). The mesh
only approximates the skin (its boundary is within `quality.surface_distance_max`
of every skin vertex of the meshed part), so a vertex just outside takes the
shape weights of its closest point on the mesh. Vertices further off (the
head, the limbs beyond the trunk's cuts) are not part of the elastic body:
their weights fade smoothly to zero over `fade` metres past that distance,
so the elastic displacement blends into the skeleton-driven skin instead of
tearing at the cut. Rows sum to 1 where the vertex belongs to the body
(a rigid translation is reproduced exactly) and to 0 far from it.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

from hitogata.fem.elements import boundary_triangles, element_order, shape_values, tet_geometry
from hitogata.volume.surface import SurfaceIndex

DEFAULT_FADE = 0.05  # m: the elastic displacement fades out over 5 cm past the mesh
_CANDIDATES = 16  # nearest tet centroids tried first; a miss retries with 4x as many
_INSIDE = -1e-9  # barycentric tolerance for "inside"
P1_EDGES = ((0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3))


def locate(points: np.ndarray, nodes: np.ndarray, tets: np.ndarray, tree: cKDTree,
           k: int = _CANDIDATES) -> tuple[np.ndarray, np.ndarray]:
    """The best tet (P,) for each point among the k with nearest centroids, and the point's
    barycentric coordinates (P, 4) in it: the tet where the smallest coordinate is largest
    (>= 0 when a candidate contains the point)."""
    k = min(k, len(tets))
    _, near = tree.query(points, k=k)
    near = near.reshape(len(points), k)
    grads, _ = tet_geometry(nodes, tets[near.ravel()])
    rel = np.repeat(points, k, axis=0) - nodes[tets[near.ravel(), 0]]
    bary = np.einsum("tij,tj->ti", grads, rel)
    bary[:, 0] += 1.0
    bary = bary.reshape(len(points), k, 4)
    best = bary.min(axis=2).argmax(axis=1)
    rows = np.arange(len(points))
    return near[rows, best], bary[rows, best]


def skin_vertex_map(vertices: np.ndarray, points: np.ndarray, elements: np.ndarray, full_distance: float,
                    fade: float = DEFAULT_FADE) -> sp.csr_matrix:
    """(V, N) matrix W with u_skin = W @ u_nodes (u_nodes: (N, 3) nodal displacements).

    points/elements: the FE mesh ((T, 4) P1 or (T, 10) P2 tets, straight-sided,
    corners first); full_distance (m): vertices this close to the mesh get
    full weight, fading to none at full_distance + fade.
    """
    vertices = np.asarray(vertices, dtype=float)
    nodes, tets = np.asarray(points, dtype=float), np.asarray(elements)[:, :4]
    # Every point of a tet is within its longest edge of a node: vertices further than
    # that from every node are out of reach and keep an empty row.
    x = nodes[tets]
    longest = max(float(np.linalg.norm(x[:, a] - x[:, b], axis=1).max()) for a, b in P1_EDGES)
    gap, _ = cKDTree(nodes).query(vertices, distance_upper_bound=full_distance + fade + longest)
    near = np.flatnonzero(np.isfinite(gap))
    tet, bary, distance = _place(vertices[near], nodes, tets)
    weights = shape_values(element_order(elements), bary) * _fade(distance, full_distance, fade)[:, None]
    rows = np.repeat(near, elements.shape[1])
    matrix = sp.csr_matrix((weights.ravel(), (rows, elements[tet].ravel())), shape=(len(vertices), len(nodes)))
    matrix.eliminate_zeros()
    return matrix


def _place(points: np.ndarray, nodes: np.ndarray, tets: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For each point: its tet, barycentric coordinates there (>= 0, summing to 1) and its
    distance to the mesh; a point outside takes the coordinates of its closest mesh point."""
    tree = cKDTree(nodes[tets].mean(axis=1))
    tet, bary = locate(points, nodes, tets, tree)
    surface = SurfaceIndex(nodes, boundary_triangles(tets))
    missed = np.flatnonzero(bary.min(axis=1) < _INSIDE)
    if missed.size:  # inside after all (the k nearest centroids missed its tet)? retry wider
        inside = missed[surface.contains(points[missed])]
        if inside.size:
            tet[inside], bary[inside] = locate(points[inside], nodes, tets, tree, 4 * _CANDIDATES)
    distance = np.zeros(len(points))
    outside = np.flatnonzero(bary.min(axis=1) < _INSIDE)
    if outside.size:
        distance[outside], closest = surface.closest(points[outside])
        tet[outside], bary[outside] = locate(closest, nodes, tets, tree)
    bary = np.clip(bary, 0.0, None)
    return tet, bary / bary.sum(axis=1, keepdims=True), distance


def _fade(distance: np.ndarray, full: float, fade: float) -> np.ndarray:
    """1 up to `full`, a half cosine down to 0 at `full + fade`, 0 beyond."""
    t = np.clip((distance - full) / max(fade, 1e-12), 0.0, 1.0)
    return 0.5 * (1.0 + np.cos(np.pi * t))
