"""Linear (P1, 4-node) and quadratic (P2, 10-node) tetrahedra.

Everything is written in barycentric coordinates L0..L3 of straight-sided
tets, whose gradients are constant per element; shape-function gradients at a
point are then a small (n, 4) table times those gradients. Node order of a P2
tet: the 4 corners, then the midpoints of the edges in ``P2_EDGES`` order.
"""

from __future__ import annotations

import numpy as np
from scipy.special import roots_jacobi

from hitogata.errors import HitogataError
from hitogata.geometry.tets import TET_FACES, on_boundary, tet_faces

#: Corner pairs of the six edges whose midpoints are P2 nodes 4..9.
P2_EDGES = np.array([[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]])


def nodes_per_element(order: int) -> int:
    """Number of nodes of a tet of the given order (1 or 2)."""
    if order == 1:
        return 4
    if order == 2:
        return 10
    raise HitogataError(f"element order {order!r} is not supported; allowed: 1 (P1) or 2 (P2)")


def element_order(tets: np.ndarray) -> int:
    """Order of a connectivity array from its width: 4 columns -> 1, 10 -> 2."""
    tets = np.asarray(tets)
    if tets.ndim == 2 and tets.shape[1] == 4:
        return 1
    if tets.ndim == 2 and tets.shape[1] == 10:
        return 2
    raise HitogataError(
        f"tets has shape {tets.shape}; allowed: (T, 4) for P1 or (T, 10) for P2 tetrahedra"
    )


def check_mesh(points: np.ndarray, tets: np.ndarray) -> None:
    """Raise HitogataError unless points are finite, indices in range and every tet has volume > 0.

    Inverted or flat tets make a stiffness matrix indefinite, so they are
    refused rather than silently assembled.
    """
    points = np.asarray(points)
    tets = np.asarray(tets)
    element_order(tets)
    if points.ndim != 2 or points.shape[1] != 3:
        raise HitogataError(f"points has shape {points.shape}; allowed: (N, 3) coordinates in metres")
    if not np.all(np.isfinite(points)):
        raise HitogataError("points contain NaN or infinite coordinates; allowed: finite values")
    if tets.size and (tets.min() < 0 or tets.max() >= len(points)):
        bad = tets.min() if tets.min() < 0 else tets.max()
        raise HitogataError(f"tet node index {bad} is out of range; allowed: 0..{len(points) - 1}")
    _, volumes = tet_geometry(points, tets)
    if volumes.size:
        worst = int(np.argmin(volumes))
        if volumes[worst] <= 0.0:
            raise HitogataError(
                f"tet {worst} is inverted or flat (signed volume {volumes[worst]:.3g} m^3); "
                "allowed: positively oriented tets with volume > 0"
            )


def tet_geometry(points: np.ndarray, tets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Barycentric-coordinate gradients (T, 4, 3) and signed volumes (T,) of the corner tets."""
    x = np.asarray(points, dtype=float)[np.asarray(tets)[:, :4]]
    jac = np.swapaxes(x[:, 1:] - x[:, :1], 1, 2)  # columns x1-x0, x2-x0, x3-x0
    det = np.linalg.det(jac)
    grads = np.empty((len(x), 4, 3))
    safe = np.where(det[:, None, None] != 0.0, jac, np.eye(3))
    grads[:, 1:] = np.linalg.inv(safe)  # rows of J^-1 are grad L1..L3
    grads[:, 0] = -grads[:, 1:].sum(axis=1)
    return grads, det / 6.0


def quadrature(degree: int) -> tuple[np.ndarray, np.ndarray]:
    """A rule exact for polynomials of the given degree on a tet.

    Returns barycentric points (Q, 4) and weights (Q,) summing to 1 (fractions
    of the tet volume). Degree <= 1: centroid; 2: the symmetric 4-point rule;
    higher: a collapsed (conical) Gauss-Jacobi product rule of any degree.
    """
    if degree < 0:
        raise HitogataError(f"quadrature degree {degree} is invalid; allowed: >= 0")
    if degree <= 1:
        return np.full((1, 4), 0.25), np.ones(1)
    if degree == 2:
        a, b = (5.0 - np.sqrt(5.0)) / 20.0, (5.0 + 3.0 * np.sqrt(5.0)) / 20.0
        return np.full((4, 4), a) + np.eye(4) * (b - a), np.full(4, 0.25)
    n = degree // 2 + 1
    pts, wts = [], []
    for alpha in (2, 1, 0):  # weights (1-u)^2, (1-v), 1 of the collapsed map
        x, w = roots_jacobi(n, alpha, 0)
        pts.append((x + 1.0) / 2.0)
        wts.append(w / 2.0 ** (alpha + 1))
    u, v, w = (g.ravel() for g in np.meshgrid(*pts, indexing="ij"))
    weight = np.einsum("i,j,k->ijk", *wts).ravel()
    l1 = u
    l2 = (1.0 - u) * v
    l3 = (1.0 - u) * (1.0 - v) * w
    bary = np.stack([1.0 - l1 - l2 - l3, l1, l2, l3], axis=1)
    return bary, weight / weight.sum()


#: Where a material that varies inside an element is sampled and integrated: the degree-4 rule
#: (27 points), exact for the P2 mass matrix and dense enough to place a tissue interface that
#: crosses an element (a 40 mm element straddles the ~20 mm skin and muscle layers).
MATERIAL_SAMPLES = quadrature(4)


def sample_points(points: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """Positions (T, Q, 3) of the material sample points of straight-sided tets (corners first)."""
    return np.einsum("qk,tkd->tqd", MATERIAL_SAMPLES[0], np.asarray(points, dtype=float)[np.asarray(tets)[:, :4]])


def shape_values(order: int, bary: np.ndarray) -> np.ndarray:
    """Shape functions (Q, n) at barycentric points (Q, 4)."""
    bary = np.atleast_2d(bary)
    if nodes_per_element(order) == 4:
        return bary.copy()
    corners = bary * (2.0 * bary - 1.0)
    edges = 4.0 * bary[:, P2_EDGES[:, 0]] * bary[:, P2_EDGES[:, 1]]
    return np.concatenate([corners, edges], axis=1)


def shape_derivatives(order: int, bary: np.ndarray) -> np.ndarray:
    """Derivatives dN/dL (Q, n, 4) of the shape functions w.r.t. the barycentric coordinates."""
    bary = np.atleast_2d(bary)
    q = len(bary)
    if nodes_per_element(order) == 4:
        return np.broadcast_to(np.eye(4), (q, 4, 4)).copy()
    d = np.zeros((q, 10, 4))
    d[:, np.arange(4), np.arange(4)] = 4.0 * bary - 1.0
    edge = np.arange(4, 10)
    d[:, edge, P2_EDGES[:, 0]] = 4.0 * bary[:, P2_EDGES[:, 1]]
    d[:, edge, P2_EDGES[:, 1]] = 4.0 * bary[:, P2_EDGES[:, 0]]
    return d


def shape_gradients(order: int, bary: np.ndarray, bary_grads: np.ndarray) -> np.ndarray:
    """Physical gradients (T, Q, n, 3) from barycentric gradients (T, 4, 3) of each tet."""
    return np.einsum("qnk,tkd->tqnd", shape_derivatives(order, bary), bary_grads)


def reference_mass(order: int) -> np.ndarray:
    """Exact (n, n) table of the integrals of N_a N_b over a tet, divided by its volume."""
    bary, w = quadrature(2 * order)
    n = shape_values(order, bary)
    return np.einsum("q,qa,qb->ab", w, n, n)


def p2_mesh(points: np.ndarray, tets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Quadratic mesh from a linear one: add one node at the midpoint of every edge.

    The original points keep their indices (0..N-1), so node sets chosen on
    the P1 mesh (e.g. bone nodes) stay valid; midpoint nodes follow.
    Returns (points (N + E, 3), tets (T, 10)).
    """
    points = np.asarray(points, dtype=float)
    tets = np.asarray(tets)
    if element_order(tets) != 1:
        raise HitogataError("p2_mesh needs a P1 mesh; allowed: tets of shape (T, 4)")
    pairs = np.sort(tets[:, P2_EDGES], axis=2).reshape(-1, 2).astype(np.int64)
    keys = pairs[:, 0] * len(points) + pairs[:, 1]
    unique, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    ends = pairs[first]
    mid = 0.5 * (points[ends[:, 0]] + points[ends[:, 1]])
    tets2 = np.concatenate([tets, len(points) + inverse.reshape(-1, 6)], axis=1)
    return np.concatenate([points, mid]), tets2


def boundary_triangles(tets: np.ndarray) -> np.ndarray:
    """Outward-oriented boundary triangles of a P1 or P2 tet mesh (`geometry.tets.boundary_faces`).

    P1 tets give (F, 3) corner triples; P2 tets give (F, 6) quadratic
    triangles: 3 corners, then the midpoints of edges (0,1), (1,2), (2,0).
    """
    tets = np.asarray(tets)
    order = element_order(tets)
    faces, once = tet_faces(tets), on_boundary(tets)
    if order == 1:
        return faces[once]
    edge_of = {tuple(e): 4 + i for i, e in enumerate(P2_EDGES.tolist())}
    local_mid = np.array(
        [[edge_of[tuple(sorted((f[i], f[(i + 1) % 3])))] for i in range(3)] for f in TET_FACES.tolist()]
    )
    mids = tets[:, local_mid].reshape(-1, 3)
    return np.concatenate([faces, mids], axis=1)[once]


def lift_node_set(tets2: np.ndarray, nodes: np.ndarray) -> np.ndarray:
    """A node set of a P1 mesh carried to its P2 mesh: the nodes plus every midpoint between two of them.

    Use it for Dirichlet sets chosen on the linear mesh (e.g. bone nodes), so
    that the edges between fixed corners are fixed too.
    """
    tets2 = np.asarray(tets2)
    if element_order(tets2) != 2:
        raise HitogataError("lift_node_set needs P2 tets; allowed: shape (T, 10)")
    nodes = np.unique(np.asarray(nodes, dtype=np.int64))
    inside = np.isin(tets2[:, :4], nodes)
    both = inside[:, P2_EDGES[:, 0]] & inside[:, P2_EDGES[:, 1]]
    return np.union1d(nodes, tets2[:, 4:][both])
