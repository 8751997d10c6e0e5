"""Checks on triangle surface meshes: topology, volume, self-intersection, inside/outside.

Every function takes plain arrays, ``vertices`` (V, 3) float and ``faces``
(F, 3) int, so the body surface, a deformed frame or a test shape can be
checked the same way. They back the claims the model makes about its surfaces
(closed, outward-oriented, no folds through itself, volume kept under motion).
"""

from __future__ import annotations

import numpy as np
from scipy import sparse
from hitogata.geometry.broad_phase import box_pairs
from hitogata.geometry.normals import triangle_normals

__all__ = [
    "boundary_edges",
    "is_closed",
    "is_consistently_oriented",
    "enclosed_volume",
    "connected_component_count",
    "euler_characteristic",
    "genus",
    "self_intersections",
    "winding_number",
    "contains",
]

# Relative tolerance (times the mesh's bounding-box diagonal) under which a
# vertex counts as lying on another triangle's plane.
_PLANE_TOLERANCE = 1e-10



# --------------------------------------------------------------------------- topology


def _faces(faces: np.ndarray) -> np.ndarray:
    return np.asarray(faces, dtype=np.int64).reshape(-1, 3)


def _edge_keys(edges: np.ndarray, n: int) -> np.ndarray:
    """Encode (E, 2) vertex-index pairs as single int64 keys, order kept."""
    return edges[:, 0] * n + edges[:, 1]


def _directed_edges(faces: np.ndarray) -> np.ndarray:
    """The 3F directed edges (a, b) of the faces, in their winding order."""
    return np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])


def _undirected_edges(faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unique undirected edges (E, 2), smaller index first, and how many faces use each."""
    edges = np.sort(_directed_edges(faces), axis=1)
    n = int(faces.max()) + 1 if faces.size else 1
    keys, counts = np.unique(_edge_keys(edges, n), return_counts=True)
    return np.stack([keys // n, keys % n], axis=1), counts


def edge_graph(vertices: np.ndarray, faces: np.ndarray) -> sparse.csr_matrix:
    """(V, V) the surface's edges, each once (smaller index first), weighted by their lengths: distances
    along the surface (`scipy.sparse.csgraph.dijkstra(..., directed=False)`)."""
    edges, _ = _undirected_edges(_faces(faces))
    vertices = np.asarray(vertices, dtype=np.float64)
    length = np.linalg.norm(vertices[edges[:, 0]] - vertices[edges[:, 1]], axis=1)
    n = len(vertices)
    return sparse.coo_matrix((length, (edges[:, 0], edges[:, 1])), shape=(n, n)).tocsr()


def boundary_edges(faces: np.ndarray) -> np.ndarray:
    """Edges (B, 2) used by exactly one face, smaller vertex index first; empty if closed."""
    edges, counts = _undirected_edges(_faces(faces))
    return edges[counts == 1]


def is_closed(faces: np.ndarray) -> bool:
    """True if every edge is shared by exactly two faces (a watertight 2-manifold edge set)."""
    faces = _faces(faces)
    if len(faces) == 0:
        return False
    _, counts = _undirected_edges(faces)
    return bool(np.all(counts == 2))


def is_consistently_oriented(faces: np.ndarray) -> bool:
    """True if each edge shared by two faces is traversed once in each direction.

    Equivalently: no directed edge occurs twice and no edge has more than two
    faces. Boundary edges are allowed, so open patches can be checked too.
    """
    faces = _faces(faces)
    if len(faces) == 0:
        return True
    n = int(faces.max()) + 1
    directed = _edge_keys(_directed_edges(faces), n)
    if len(np.unique(directed)) != len(directed):
        return False
    _, counts = _undirected_edges(faces)
    return bool(counts.max() <= 2)


def enclosed_volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    """Signed volume enclosed by a closed surface (divergence theorem).

    Positive when face normals (right-hand rule on the vertex order) point
    outward, negative when the surface is inside out.
    """
    tri = np.asarray(vertices, dtype=np.float64)[_faces(faces)]
    triple = np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2]))
    return float(triple.sum() / 6.0)


def connected_component_count(faces: np.ndarray) -> int:
    """Number of edge-connected pieces of the surface (vertices not in any face are ignored)."""
    faces = _faces(faces)
    if len(faces) == 0:
        return 0
    used, local = np.unique(faces, return_inverse=True)
    local = local.reshape(-1, 3)
    edges = _directed_edges(local)
    graph = sparse.coo_matrix(
        (np.ones(len(edges), dtype=np.int8), (edges[:, 0], edges[:, 1])),
        shape=(len(used), len(used)),
    )
    from scipy.sparse import csgraph  # here: its import (with scipy.sparse.linalg) outweighs a body's volume

    count, _ = csgraph.connected_components(graph, directed=False)
    return int(count)


def euler_characteristic(faces: np.ndarray) -> int:
    """V − E + F over the vertices and edges the faces use."""
    faces = _faces(faces)
    edges, _ = _undirected_edges(faces)
    return int(len(np.unique(faces)) - len(edges) + len(faces))


def genus(faces: np.ndarray) -> int:
    """Total genus (number of handles) of a closed orientable surface: C − χ/2.

    Raises ValueError for an open surface, where genus is not defined this way.
    """
    faces = _faces(faces)
    if not is_closed(faces):
        raise ValueError("genus is defined here for closed surfaces only; the mesh has boundary edges")
    twice = 2 * connected_component_count(faces) - euler_characteristic(faces)
    return twice // 2


# --------------------------------------------------------------------------- self-intersection


def self_intersections(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Pairs (K, 2) of face indices, i < j, whose triangles intersect.

    Pairs sharing a vertex index are skipped (neighbours always touch there),
    so a fold between such neighbours is not reported; contact between
    triangles that only touch counts as intersection, so the mesh should be
    welded. Degenerate (zero-area) triangles are never reported. Broad phase:
    the triangles' bounding boxes by size class in k-d trees (`broad_phase.box_pairs`); narrow phase: an exact
    triangle-triangle test (interval overlap on the planes' common line, or a
    2-D test for coplanar pairs). Rows are sorted.
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = _faces(faces)
    if len(faces) < 2:
        return np.empty((0, 2), dtype=np.int64)
    tri = vertices[faces]
    lo, hi = tri.min(axis=1), tri.max(axis=1)
    i, j = _apart(faces, *box_pairs(lo, hi)).T
    tolerance = _PLANE_TOLERANCE * float(np.linalg.norm(hi.max(axis=0) - lo.min(axis=0)))
    hit = _triangles_intersect(tri[i], tri[j], tolerance)
    pairs = np.stack([i[hit], j[hit]], axis=1)
    return pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))]


def _apart(faces: np.ndarray, i: np.ndarray, j: np.ndarray) -> np.ndarray:
    """(K, 2) the face pairs (i, j) that share no vertex: touching neighbours never count as crossing."""
    apart = ~(faces[i][:, :, None] == faces[j][:, None, :]).any(axis=(1, 2))
    return np.stack([i[apart], j[apart]], axis=1)


def _plane_distances(points: np.ndarray, tri: np.ndarray, unit_normal: np.ndarray, tolerance: float) -> np.ndarray:
    """Signed distances (K, 3) of each triangle's vertices from the other's plane; tiny ones set to 0."""
    d = np.einsum("kvi,ki->kv", points - tri[:, :1], unit_normal)
    d[np.abs(d) <= tolerance] = 0.0
    return d


def _triangles_intersect(a: np.ndarray, b: np.ndarray, tolerance: float) -> np.ndarray:
    """Whether triangles a[k] and b[k] (K, 3, 3) intersect (touching included)."""
    na = triangle_normals(a)
    nb = triangle_normals(b)
    la = np.linalg.norm(na, axis=1)
    lb = np.linalg.norm(nb, axis=1)
    valid = (la > 0) & (lb > 0)
    with np.errstate(invalid="ignore", divide="ignore"):
        ua, ub = na / la[:, None], nb / lb[:, None]
    da = _plane_distances(a, b, ub, tolerance)
    db = _plane_distances(b, a, ua, tolerance)

    def one_side(d: np.ndarray) -> np.ndarray:
        return np.all(d > 0, axis=1) | np.all(d < 0, axis=1)

    maybe = valid & ~one_side(da) & ~one_side(db)
    coplanar = np.all(da == 0, axis=1) | np.all(db == 0, axis=1)
    hit = np.zeros(len(a), dtype=bool)

    crossing = maybe & ~coplanar
    if crossing.any():
        direction = np.cross(ua[crossing], ub[crossing])
        origin = a[crossing][:, :1]
        pa = np.einsum("kvi,ki->kv", a[crossing] - origin, direction)
        pb = np.einsum("kvi,ki->kv", b[crossing] - origin, direction)
        lo_a, hi_a = _interval_on_line(pa, da[crossing])
        lo_b, hi_b = _interval_on_line(pb, db[crossing])
        hit[crossing] = (lo_a <= hi_b) & (lo_b <= hi_a)

    flat = maybe & coplanar
    if flat.any():
        hit[flat] = _coplanar_intersect(a[flat], b[flat], na[flat])
    return hit


def _interval_on_line(p: np.ndarray, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Extent along the planes' common line of a triangle's part on the other plane.

    ``p`` are the vertices' coordinates along the line, ``d`` their signed
    distances to the other plane; the part is the hull of vertices on the plane
    and of edge crossings.
    """
    values = np.where(d == 0, p, np.nan)
    crossings = []
    for u, v in ((0, 1), (1, 2), (2, 0)):
        sign_change = d[:, u] * d[:, v] < 0
        with np.errstate(invalid="ignore", divide="ignore"):
            t = p[:, u] + (p[:, v] - p[:, u]) * d[:, u] / (d[:, u] - d[:, v])
        crossings.append(np.where(sign_change, t, np.nan))
    values = np.concatenate([values, np.stack(crossings, axis=1)], axis=1)
    known = ~np.isnan(values)
    return (
        np.where(known, values, np.inf).min(axis=1),
        np.where(known, values, -np.inf).max(axis=1),
    )


def _orient(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Twice the signed area of 2-D triangles (a, b, c); broadcasts over leading axes."""
    return (b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1]) - (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0])


def _coplanar_intersect(a: np.ndarray, b: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Intersection of coplanar triangle pairs, tested in 2-D after dropping the normal's main axis.

    They meet iff an edge of one properly crosses an edge of the other or a
    vertex of one lies in the other (closed) triangle.
    """
    kept = np.array([[1, 2], [0, 2], [0, 1]])[np.abs(normal).argmax(axis=1)]
    a2 = np.take_along_axis(a, kept[:, None, :], axis=2)
    b2 = np.take_along_axis(b, kept[:, None, :], axis=2)

    def inside(points: np.ndarray, tri: np.ndarray) -> np.ndarray:
        t = tri[:, None]
        s = np.stack(
            [_orient(t[..., 0, :], t[..., 1, :], points),
             _orient(t[..., 1, :], t[..., 2, :], points),
             _orient(t[..., 2, :], t[..., 0, :], points)],
            axis=-1,
        )
        return (np.all(s >= 0, axis=-1) | np.all(s <= 0, axis=-1)).any(axis=1)

    a0, a1 = a2[:, :, None], np.roll(a2, -1, axis=1)[:, :, None]
    b0, b1 = b2[:, None], np.roll(b2, -1, axis=1)[:, None]
    cross = (
        (_orient(a0, a1, b0) * _orient(a0, a1, b1) < 0)
        & (_orient(b0, b1, a0) * _orient(b0, b1, a1) < 0)
    ).any(axis=(1, 2))
    return cross | inside(a2, b2) | inside(b2, a2)


# --------------------------------------------------------------------------- inside / outside


def winding_number(vertices: np.ndarray, faces: np.ndarray, points: np.ndarray, fast: bool = False) -> np.ndarray:
    """Generalized winding number (P,) of the surface around each point (Jacobson, Kavan &
    Sorkine-Hornung 2013): 1 inside and 0 outside a closed outward-oriented surface, a smooth
    inside-ness measure for surfaces with small holes, k where k sheets cover the point.

    libigl's: the exact sum of the triangles' signed solid angles over 4π, or with `fast` its
    hierarchical approximation (Barill et al. 2018; within 0.004 of the exact one on the body's skin).
    """
    import igl  # here: a body's volume needs no libigl

    v = np.ascontiguousarray(vertices, dtype=np.float64)
    f = np.ascontiguousarray(_faces(faces), dtype=np.int64)
    p = np.ascontiguousarray(np.asarray(points, dtype=np.float64).reshape(-1, 3))
    if not len(f) or not len(p):
        return np.zeros(len(p))
    return np.asarray((igl.fast_winding_number if fast else igl.winding_number)(v, f, p), dtype=np.float64)


def contains(vertices: np.ndarray, faces: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Boolean (P,): whether each point is inside the surface (winding number > 0.5)."""
    return winding_number(vertices, faces, points) > 0.5
