"""From nodal displacements to the body's skin vertices: a sparse interpolation matrix.

Each skin vertex is bound to one tet and weighted by that tet's shape
functions at the vertex (barycentric for P1, quadratic for P2). The binding
only ever reaches tissue that moves with the vertex:

- only tets of the body's piece count: the largest set of tets joined through
  shared faces. A lattice island or a tet hanging on by an edge or a corner
  has no equilibrium of its own (it hinges), so a vertex bound to it would be
  thrown with it (a 240 mm jump at the ankle on the male whole body);
- with part weights given (the vertex's skinning weights and the nodes'), only
  tets whose every corner shares at least `AGREEMENT` of its weight with the
  vertex count: a tet bridging the air between two limbs, or the other limb
  nearest across a gap, is never used;
- a vertex inside such a tet takes its shape weights there; a vertex outside
  takes those of its closest point on the boundary of an admissible tet.

The mesh only approximates the skin, so vertices within `reach` of their
closest point get full weight; further off (parts the mesh does not hold, the
limbs beyond a trunk's cuts) the weight fades smoothly to zero over `fade`
metres, so the elastic displacement blends into the skeleton-driven skin.
Rows sum to 1 where the vertex belongs to the body (a rigid translation is
reproduced exactly) and to 0 far from it.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

from hitogata.fem.elements import element_order, shape_values, tet_geometry
from hitogata.geometry.tets import on_boundary, tet_faces
from hitogata.volume.integrity import face_pieces
from hitogata.geometry.closest import nearest_on_triangles

DEFAULT_FADE = 0.05  # m: the elastic displacement fades out over 5 cm past `reach`
# Full weight reaches half an element past the mesh at most: where the mesh holds a part its
# boundary lies that close to the skin (the default bodies' torso skin, trunk or whole body:
# within 9-14 mm at 40 mm, 13-17 mm at 60 mm); further off the mesh does not hold the part.
REACH = 0.5
# Least share of part weight each corner of a tet has in common with a vertex bound to it
# (sum over parts of min(w_vertex, w_node)): 0 for a tet reaching another limb, ~0.5 for a
# vertex halfway along a joint and a corner on the bone of one side.
AGREEMENT = 0.25
_CANDIDATES = 16  # nearest tet centroids (or boundary faces) tried first; a miss retries with 4x as many
_INSIDE = -1e-9  # barycentric tolerance for "inside"
_BLOCK = 1024  # vertices per block of candidate tests (bounds the temporaries)


def skin_reach(surface_distance_max: float, element_size: float) -> float:
    """Distance (m) within which a skin vertex takes its bound point's full displacement: the
    mesh's surface distance, at most REACH of an element (beyond, a part the mesh does not hold)."""
    return min(surface_distance_max, REACH * element_size)


def body_piece(tets: np.ndarray) -> np.ndarray:
    """(T,) bool: the tets of the largest face-connected piece (by count; `volume.integrity.face_pieces`)."""
    return face_pieces(np.asarray(tets)[:, :4]) == 0


def skin_vertex_map(vertices: np.ndarray, points: np.ndarray, elements: np.ndarray, reach: float,
                    fade: float = DEFAULT_FADE, vertex_weights: sp.spmatrix | np.ndarray | None = None,
                    node_weights: sp.spmatrix | np.ndarray | None = None) -> sp.csr_matrix:
    """(V, N) matrix W with u_skin = W @ u_nodes (u_nodes: (N, 3) nodal displacements).

    points/elements: the FE mesh ((T, 4) P1 or (T, 10) P2 tets, straight-sided,
    corners first); reach (m): vertices this close to their bound point get full
    weight, fading to none at reach + fade. vertex_weights (V, P) / node_weights
    (N, P): part weights (rows summing to 1) of the skin vertices and the nodes;
    with them a vertex binds only to tets whose corners move with its parts.
    """
    vertices = np.asarray(vertices, dtype=float)
    nodes, elements = np.asarray(points, dtype=float), np.asarray(elements)
    keep = np.flatnonzero(body_piece(elements))
    tets = elements[keep, :4]
    agree = _agreement(vertex_weights, node_weights)
    # Every point of a tet is within its longest edge of a node: vertices further than that
    # (plus the reach and fade) from every node of the piece are out of reach: empty rows.
    used = np.unique(tets)
    x = nodes[tets]
    longest = float(np.linalg.norm(x[:, :, None] - x[:, None], axis=3).max())
    gap, _ = cKDTree(nodes[used]).query(vertices, distance_upper_bound=reach + fade + longest)
    near = np.flatnonzero(np.isfinite(gap))
    tet, bary, distance = _place(vertices[near], near, nodes, tets, agree)
    found = np.isfinite(distance)
    near, tet, bary, distance = near[found], tet[found], bary[found], distance[found]
    weights = shape_values(element_order(elements), bary) * _fade(distance, reach, fade)[:, None]
    rows = np.repeat(near, elements.shape[1])
    cols = elements[keep[tet]].ravel()
    matrix = sp.csr_matrix((weights.ravel(), (rows, cols)), shape=(len(vertices), len(nodes)))
    matrix.eliminate_zeros()
    return matrix


def _agreement(vertex_weights, node_weights):
    """A test (vertex ids (K,), corner node ids (K, 4)) -> (K,) bool: every corner shares at least
    AGREEMENT of its part weight with the vertex; None without weights."""
    if vertex_weights is None or node_weights is None:
        return None
    wv, wn = (np.asarray(w.toarray() if sp.issparse(w) else w, dtype=np.float32)
              for w in (vertex_weights, node_weights))

    def test(vertex: np.ndarray, corners: np.ndarray) -> np.ndarray:
        out = np.ones(len(vertex), dtype=bool)
        for c in range(corners.shape[1]):
            out &= np.minimum(wv[vertex], wn[corners[:, c]]).sum(axis=1) >= AGREEMENT
        return out

    return test


def _candidates(points: np.ndarray, nodes: np.ndarray, tets: np.ndarray, tree: cKDTree,
                k: int) -> tuple[np.ndarray, np.ndarray]:
    """The k tets with nearest centroids (P, k) and the points' barycentric coordinates (P, k, 4) in them."""
    k = min(k, len(tets))
    _, near = tree.query(points, k=k)
    near = near.reshape(len(points), k)
    grads, _ = tet_geometry(nodes, tets[near.ravel()])
    rel = np.repeat(points, k, axis=0) - nodes[tets[near.ravel(), 0]]
    bary = np.einsum("tij,tj->ti", grads, rel)
    bary[:, 0] += 1.0
    return near, bary.reshape(len(points), k, 4)


def _place(points: np.ndarray, ids: np.ndarray, nodes: np.ndarray, tets: np.ndarray,
           agree) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For each point: its tet, barycentric coordinates there (>= 0, summing to 1) and its distance
    to that tet (0 inside; inf where no admissible tet is near). A point inside no admissible tet
    takes its closest point on the boundary of an admissible tet.

    ids: the points' vertex indices (for `agree`, the part-weight test, or None).
    """
    tree = cKDTree(nodes[tets].mean(axis=1))
    tet = np.zeros(len(points), dtype=np.int64)
    bary = np.zeros((len(points), 4))
    distance = np.full(len(points), np.inf)
    for start in range(0, len(points), _BLOCK):
        block = slice(start, start + _BLOCK)
        for k in (_CANDIDATES, 4 * _CANDIDATES):
            todo = np.flatnonzero(distance[block] > 0) + start
            if not todo.size:
                break
            near, b = _candidates(points[todo], nodes, tets, tree, k)
            ok = np.ones(near.shape, dtype=bool) if agree is None else agree(
                np.repeat(ids[todo], near.shape[1]), tets[near.ravel()]).reshape(near.shape)
            inside = ok & (b.min(axis=2) >= _INSIDE)
            hit = inside.any(axis=1)
            pick = inside.argmax(axis=1)[hit]
            tet[todo[hit]] = near[hit, pick]
            bary[todo[hit]] = b[hit, pick]
            distance[todo[hit]] = 0.0
    outside = np.flatnonzero(distance > 0)
    if outside.size:
        tet[outside], bary[outside], distance[outside] = _closest_on_boundary(points[outside], ids[outside],
                                                                              nodes, tets, agree)
    bary = np.clip(bary, 0.0, None)
    return tet, bary / np.maximum(bary.sum(axis=1, keepdims=True), 1e-300), distance


def _closest_on_boundary(points: np.ndarray, ids: np.ndarray, nodes: np.ndarray, tets: np.ndarray,
                         agree) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each point's closest point on the boundary faces of admissible tets: that face's tet,
    the closest point's barycentric coordinates in it, and the distance (inf: none near)."""
    faces = tet_faces(tets)
    outer = np.flatnonzero(on_boundary(tets))
    owner, tri = outer // 4, nodes[faces[outer]]
    admissible = None if agree is None else (lambda rows, near: agree(ids[rows], tets[owner[near]]))
    distance, face, closest = nearest_on_triangles(cKDTree(tri.mean(axis=1)), tri, points, 4 * _CANDIDATES,
                                                   admissible)
    tet = owner[face]
    grads, _ = tet_geometry(nodes, tets[tet])
    bary = np.einsum("tij,tj->ti", grads, closest - nodes[tets[tet, 0]])
    bary[:, 0] += 1.0
    return tet, bary, distance


def _fade(distance: np.ndarray, full: float, fade: float) -> np.ndarray:
    """1 up to `full`, a half cosine down to 0 at `full + fade`, 0 beyond."""
    t = np.clip((distance - full) / max(fade, 1e-12), 0.0, 1.0)
    return 0.5 * (1.0 + np.cos(np.pi * t))
