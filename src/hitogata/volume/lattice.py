"""Isosurface stuffing: a tetrahedral mesh of a domain from a body-centred cubic lattice.

Our implementation of Labelle & Shewchuk, "Isosurface stuffing: fast tetrahedral
meshes with good dihedral angles", ACM SIGGRAPH 2007 (uniform variant):

1. The BCC lattice of spacing h: the corners of a cubic grid and the centres
   of its cubes. Its edges are long (corner–corner and centre–centre, length
   h) or short (centre–corner, √3/2 h); its tetrahedra (two centres and one
   edge of the square face between their cubes) have dihedral angles of
   60° and 90° only.
2. Every lattice vertex is classified inside (−) or outside (+); every edge
   whose ends differ is cut where it leaves the domain.
3. A vertex too close to a cut point on one of its edges (closer than α of
   the edge length: α = 0.24999 on long edges, 0.41189 on short ones, the
   paper's values for dihedral angles between 10.7° and 164.8°) is *warped*
   onto the nearest such cut point and becomes a boundary vertex (0); cut
   points on its edges disappear.
4. Each lattice tetrahedron with a vertex ≤ 0 is replaced by its part inside
   the domain, from a small set of stencils keyed by its vertices' signs.

Stencils that cut a lattice face into a quadrilateral (two − vertices and one
+) must split it the same way from both sides. The paper's parity rule does
this; we use the global order of the lattice vertices instead: the diagonal
joins the − vertex with the smaller index to the cut point on the other − vertex's
edge. This is consistent across faces and never cyclic round a prism
(Dompierre et al. 1999, "How to subdivide pyramids, prisms and hexahedra into
tetrahedra"), so every stencil splits without extra vertices. The paper's
angle proof covers its own rule; with ours the bounds are measured (see
`benchmarks/bench_volume.py` and the tests), not proved.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.volume.domain import Domain

ALPHA_LONG = 0.24999  # Labelle & Shewchuk 2007, Table 1: the 10.7°–164.8° parameter set
ALPHA_SHORT = 0.41189
MIN_DIHEDRAL = np.radians(10.7)  # the paper's lower bound for these α

# Lattice offset in units of h: breaks the alignment of lattice planes with
# planar boundaries (a box, a cut plane) that would make cut points coincide
# with lattice vertices.
_SHIFT = np.array([0.1372, 0.2853, 0.4219])


@dataclass(frozen=True)
class TetMesh:
    """Nodes (N, 3), positively oriented tets (T, 4), and for each node the index of the
    domain boundary part it lies on (-1 for interior nodes)."""

    nodes: np.ndarray
    tets: np.ndarray
    node_part: np.ndarray


@dataclass(frozen=True)
class _Lattice:
    origin: np.ndarray
    spacing: float
    n: np.ndarray  # cubes per axis; corners are (n+1)^3, centres n^3

    @property
    def n_corners(self) -> int:
        return int(np.prod(self.n + 1))

    def corner(self, i: np.ndarray, j: np.ndarray, k: np.ndarray) -> np.ndarray:
        return (i * (self.n[1] + 1) + j) * (self.n[2] + 1) + k

    def centre(self, i: np.ndarray, j: np.ndarray, k: np.ndarray) -> np.ndarray:
        return self.n_corners + (i * self.n[1] + j) * self.n[2] + k

    def points(self) -> np.ndarray:
        grids = [np.indices(tuple(self.n + 1)).reshape(3, -1).T, np.indices(tuple(self.n)).reshape(3, -1).T + 0.5]
        return self.origin + self.spacing * np.concatenate(grids).astype(np.float64)

    def edges(self) -> list[tuple[np.ndarray, bool]]:
        """Lattice edges as (E, 2) vertex pairs, per family, with a flag: long edge?"""
        out = []
        for axis in range(3):
            step = np.eye(3, dtype=np.int64)[axis]
            ijk = np.indices(tuple(self.n + 1 - step)).reshape(3, -1)
            out.append((np.stack([self.corner(*ijk), self.corner(*(ijk + step[:, None]))], axis=1), True))
            ijk = np.indices(tuple(self.n - step)).reshape(3, -1)
            out.append((np.stack([self.centre(*ijk), self.centre(*(ijk + step[:, None]))], axis=1), True))
        ijk = np.indices(tuple(self.n)).reshape(3, -1)
        for corner in np.indices((2, 2, 2)).reshape(3, -1).T:
            out.append((np.stack([self.centre(*ijk), self.corner(*(ijk + corner[:, None]))], axis=1), False))
        return out

    def tets(self) -> np.ndarray:
        """All lattice tets (T, 4): centres c, c+e_axis and one edge of their shared square."""
        out = []
        for axis in range(3):
            a1, a2 = (axis + 1) % 3, (axis + 2) % 3
            e, e1, e2 = (np.eye(3, dtype=np.int64)[d][:, None] for d in (axis, a1, a2))
            ijk = np.indices(tuple(self.n - e.ravel())).reshape(3, -1)
            c0, c1 = self.centre(*ijk), self.centre(*(ijk + e))
            square = [self.corner(*(ijk + e + o)) for o in (0 * e, e1, e1 + e2, e2)]
            for q in range(4):
                out.append(np.stack([c0, c1, square[q], square[(q + 1) % 4]], axis=1))
        return np.concatenate(out)


def stuff(domain: Domain, spacing: float, bounds: tuple[np.ndarray, np.ndarray]) -> TetMesh:
    """Tetrahedral mesh of `domain` (which lies within the box `bounds`) with lattice spacing h (m)."""
    lo, hi = (np.asarray(b, dtype=np.float64) for b in bounds)
    origin = lo - spacing * (1.0 + _SHIFT)
    lattice = _Lattice(origin, float(spacing), np.ceil((hi - origin) / spacing).astype(np.int64) + 1)
    x = lattice.points()
    sign = np.where(domain.contains(x), -1, 1).astype(np.int8)
    part = np.full(len(x), -1, dtype=np.int64)

    a, b, t_a, cut_part, long = _cut_edges(domain, lattice, x, sign)
    _warp(x, sign, part, a, b, t_a, cut_part, long, spacing)

    keep = (sign[a] != 0) & (sign[b] != 0)
    a, b, t_a, cut_part = a[keep], b[keep], t_a[keep], cut_part[keep]
    cut_nodes = x[a] + (x[b] - x[a]) * t_a[:, None]
    n_lattice = len(x)
    keys = np.minimum(a, b) * n_lattice + np.maximum(a, b)
    order = np.argsort(keys)
    keys, cut_id = keys[order], n_lattice + order

    tets = lattice.tets()
    tets = tets[(sign[tets] <= 0).any(axis=1)]
    nodes = np.concatenate([x, cut_nodes])
    part = np.concatenate([part, cut_part])

    def cut(u: np.ndarray, v: np.ndarray) -> np.ndarray:
        return cut_id[np.searchsorted(keys, np.minimum(u, v) * n_lattice + np.maximum(u, v))]

    out = _stencils(tets, sign, cut, nodes, domain)
    return _compact(nodes, out, part)


def _cut_edges(domain: Domain, lattice: _Lattice, x: np.ndarray, sign: np.ndarray):
    """Edges whose ends differ in sign, with the cut fraction measured from their first end."""
    pairs, flags = [], []
    for edges, is_long in lattice.edges():
        edges = edges[sign[edges[:, 0]] != sign[edges[:, 1]]]
        pairs.append(edges)
        flags.append(np.full(len(edges), is_long))
    e = np.concatenate(pairs)
    long = np.concatenate(flags)
    a, b = e[:, 0], e[:, 1]
    a_inside = sign[a] < 0
    inner, outer = np.where(a_inside, a, b), np.where(a_inside, b, a)
    t, cut_part = domain.exit(x[inner], x[outer])
    return a, b, np.where(a_inside, t, 1.0 - t), cut_part, long


def _warp(x, sign, part, a, b, t_a, cut_part, long, spacing) -> None:
    """Move each vertex violated by a cut point on one of its edges onto the nearest such point."""
    alpha = np.where(long, ALPHA_LONG, ALPHA_SHORT)
    length = np.where(long, 1.0, np.sqrt(3.0) / 2.0) * spacing
    vertex = np.concatenate([a[t_a < alpha], b[1.0 - t_a < alpha]])
    edge = np.concatenate([np.flatnonzero(t_a < alpha), np.flatnonzero(1.0 - t_a < alpha)])
    dist = np.concatenate([t_a[t_a < alpha], (1.0 - t_a)[1.0 - t_a < alpha]]) * length[edge]
    order = np.lexsort((edge, dist, vertex))
    vertex, edge = vertex[order], edge[order]
    first = np.ones(len(vertex), dtype=bool)
    first[1:] = vertex[1:] != vertex[:-1]
    vertex, edge = vertex[first], edge[first]
    cut_points = x[a[edge]] + (x[b[edge]] - x[a[edge]]) * t_a[edge, None]
    x[vertex] = cut_points
    sign[vertex] = 0
    part[vertex] = cut_part[edge]


def _stencils(tets: np.ndarray, sign: np.ndarray, cut, nodes: np.ndarray, domain: Domain) -> np.ndarray:
    """The domain's part of each lattice tet, as output tets (any orientation)."""
    s = sign[tets].astype(np.int64)
    n_lattice = len(sign)
    order = np.argsort((s + 1) * n_lattice + tets, axis=1)  # − first, then 0, then +; by index within
    v = np.take_along_axis(tets, order, axis=1)
    n_minus, n_plus = (s < 0).sum(axis=1), (s > 0).sum(axis=1)
    out = [v[(n_minus > 0) & (n_plus == 0)]]

    # All four vertices warped onto the boundary: the tet lies along it. Keep it if it is
    # inside and no worse than the stencils' bound; otherwise the boundary passes over it.
    zero = v[(n_minus == 0) & (n_plus == 0)]
    zero = zero[domain.contains(nodes[zero].mean(axis=1))]
    out.append(zero[_min_dihedral(nodes[zero]) >= MIN_DIHEDRAL])

    def case(m: int, p: int) -> np.ndarray:
        return v[(n_minus == m) & (n_plus == p)]

    t = case(1, 1)  # m z z p
    out.append(np.stack([t[:, 0], t[:, 1], t[:, 2], cut(t[:, 0], t[:, 3])], axis=1))
    t = case(1, 2)  # m z p p
    out.append(np.stack([t[:, 0], t[:, 1], cut(t[:, 0], t[:, 2]), cut(t[:, 0], t[:, 3])], axis=1))
    t = case(1, 3)  # m p p p
    out.append(np.stack([t[:, 0], *(cut(t[:, 0], t[:, k]) for k in (1, 2, 3))], axis=1))
    t = case(2, 1)  # m1 m2 z p: pyramid on the quad m1 m2 c2 c1, diagonal m1–c2
    c1, c2 = cut(t[:, 0], t[:, 3]), cut(t[:, 1], t[:, 3])
    out.append(np.stack([t[:, 2], t[:, 0], t[:, 1], c2], axis=1))
    out.append(np.stack([t[:, 2], t[:, 0], c2, c1], axis=1))
    t = case(2, 2)  # m1 m2 p1 p2: prism, both lattice-face diagonals from m1
    m1, m2 = t[:, 0], t[:, 1]
    c11, c12, c21, c22 = cut(m1, t[:, 2]), cut(m1, t[:, 3]), cut(m2, t[:, 2]), cut(m2, t[:, 3])
    out.append(np.stack([m1, m2, c21, c22], axis=1))
    # The quad c11 c21 c22 c12 lies on the boundary, inside this lattice tet: split it
    # along its shorter diagonal.
    short = np.linalg.norm(nodes[c11] - nodes[c22], axis=1) <= np.linalg.norm(nodes[c12] - nodes[c21], axis=1)
    s_ = short[:, None]
    out.append(np.where(s_, np.stack([m1, c11, c21, c22], axis=1), np.stack([m1, c11, c12, c21], axis=1)))
    out.append(np.where(s_, np.stack([m1, c11, c22, c12], axis=1), np.stack([m1, c12, c22, c21], axis=1)))
    t = case(3, 1)  # m1 m2 m3 p: prism, diagonals m1–c2, m1–c3, m2–c3
    c1, c2, c3 = (cut(t[:, k], t[:, 3]) for k in range(3))
    out.append(np.stack([t[:, 0], c1, c2, c3], axis=1))
    out.append(np.stack([t[:, 0], t[:, 1], t[:, 2], c3], axis=1))
    out.append(np.stack([t[:, 0], t[:, 1], c3, c2], axis=1))
    return np.concatenate(out)


def _min_dihedral(p: np.ndarray) -> np.ndarray:
    """Smallest dihedral angle (T,) of tets given by corner coordinates (T, 4, 3), radians."""
    faces = ((1, 2, 3), (0, 3, 2), (0, 1, 3), (0, 2, 1))
    n = np.stack([np.cross(p[:, b] - p[:, a], p[:, c] - p[:, a]) for a, b, c in faces], axis=1)
    n /= np.linalg.norm(n, axis=2, keepdims=True)
    cos = np.stack([np.einsum("ij,ij->i", n[:, i], n[:, j]) for i in range(4) for j in range(i + 1, 4)], axis=1)
    return np.pi - np.arccos(np.clip(cos, -1.0, 1.0)).max(axis=1)


def _compact(nodes: np.ndarray, tets: np.ndarray, part: np.ndarray) -> TetMesh:
    """Drop unused nodes, renumber, and orient every tet positively."""
    used, inverse = np.unique(tets, return_inverse=True)
    tets = inverse.reshape(-1, 4).astype(np.int64)
    nodes = nodes[used]
    p = nodes[tets]
    det = np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]))
    tets[det < 0] = tets[det < 0][:, [0, 1, 3, 2]]
    return TetMesh(nodes=nodes, tets=tets, node_part=part[used])
