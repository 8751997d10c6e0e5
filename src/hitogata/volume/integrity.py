"""Is a tetrahedral mesh one piece, joined through faces, with a manifold boundary, and held well?

The finite-element body needs more of its mesh than good angles:

- every piece (tets joined through shared faces) must be held by the
  skeleton at three nodes that span a real triangle, or it floats or
  hinges: a zero or near-zero frequency (a piece of five skin tets on three
  nearly collinear capsule nodes rang at 0.0115 Hz);
- no tet may be joined to the rest by an edge or a vertex only: such a joint
  carries no stress, so the tet hinges about it;
- the boundary must be a closed 2-manifold (each edge on two boundary
  triangles, each vertex's boundary triangles one fan), or the skin map,
  pictures and contact see a pinched surface.

`mesh_integrity` measures all of these; `face_pieces`, `pinched_vertices`,
`pinched_edges` and `hold_width` are the parts.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from hitogata.geometry.tets import shared_face_pairs
from hitogata.geometry.unique import unique_rows
from hitogata.volume.quality import boundary_faces, dihedral_angles

# The held nodes of every piece must span a triangle whose smallest height is at least this
# (m): a quarter of the default 40 mm element, half the smallest bone capsule's radius. A piece
# held along a line (height 0) hinges; at 10 mm its held base is a real triangle of tissue.
MIN_HOLD_WIDTH = 0.010
# Smallest dihedral angle (degrees) the body's mesh must keep.
MIN_DIHEDRAL = 10.0

TET_EDGES = np.array([[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]])


@dataclass(frozen=True)
class MeshIntegrity:
    """What makes a mesh one well-held piece (lengths m, angles degrees)."""

    n_pieces: int  # tets joined through shared faces
    pinched_vertices: int  # vertices whose tets fall apart into groups that share no face through them
    pinched_edges: int  # edges whose tets fall apart likewise (joined by the edge only)
    non_manifold_edges: int  # boundary edges on other than two boundary triangles
    non_manifold_vertices: int  # boundary vertices whose boundary triangles form more than one fan
    weakest_hold: float  # over the pieces: smallest height of the triangle their held nodes span
    min_dihedral: float

    @property
    def ok(self) -> bool:
        """No pinch (so pieces share no node), a closed 2-manifold boundary, every piece held across
        `MIN_HOLD_WIDTH`, dihedral angles ≥ `MIN_DIHEDRAL`."""
        return (self.pinched_vertices == 0 and self.pinched_edges == 0 and self.non_manifold_edges == 0
                and self.non_manifold_vertices == 0 and self.weakest_hold >= MIN_HOLD_WIDTH
                and self.min_dihedral >= MIN_DIHEDRAL)

    def summary(self) -> str:
        return (f"{self.n_pieces} piece(s), {self.pinched_vertices} pinched vertices, {self.pinched_edges} pinched "
                f"edges, boundary: {self.non_manifold_edges} non-manifold edges, {self.non_manifold_vertices} "
                f"non-manifold vertices; weakest hold {self.weakest_hold * 1e3:.1f} mm, "
                f"min dihedral {self.min_dihedral:.1f}°")


def mesh_integrity(nodes: np.ndarray, tets: np.ndarray, held: np.ndarray) -> MeshIntegrity:
    """Measure a tet mesh (nodes (N, 3) m, tets (T, 4)) whose nodes `held` (indices) follow the skeleton."""
    piece = face_pieces(tets)
    faces, _ = boundary_faces(tets)
    widths = [hold_width(nodes[np.intersect1d(np.unique(tets[piece == k]), held)]) for k in range(piece.max() + 1)]
    return MeshIntegrity(
        n_pieces=int(piece.max() + 1),
        pinched_vertices=len(pinched_vertices(tets)),
        pinched_edges=len(pinched_edges(tets)),
        non_manifold_edges=len(non_manifold_edges(faces)),
        non_manifold_vertices=len(non_manifold_vertices(faces)),
        weakest_hold=float(min(widths)),
        min_dihedral=float(np.degrees(dihedral_angles(nodes, tets).min())),
    )


def _shared_faces(tets: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pairs of tets (a, b) sharing a face, and that face's local index (0–3) in a."""
    first, second = shared_face_pairs(tets)
    return first // 4, second // 4, first % 4


def face_pieces(tets: np.ndarray) -> np.ndarray:
    """Piece label (T,) of each tet: tets joined through shared faces; 0 is the largest piece."""
    a, b, _ = _shared_faces(tets)
    graph = sp.csr_matrix((np.ones(len(a), dtype=np.int8), (a, b)), shape=(len(tets), len(tets)))
    _, label = connected_components(graph, directed=False)
    rank = np.argsort(np.argsort(-np.bincount(label), kind="stable"), kind="stable")
    return rank[label]


def star_groups(tets: np.ndarray, local: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Split the tets round each simplex into groups joined through faces that hold the simplex.

    `local` (k, m) gives the k simplices of a tet by corner (vertices: (4, 1), edges: (6, 2)).
    Returns the simplices (S, m), and for each incidence (tet t, simplex s) = k t + s its
    simplex (index into them) and its group label (global).
    """
    n, k = len(tets), len(local)
    keys, key = unique_rows(np.sort(tets[:, local], axis=2).reshape(n * k, -1), return_inverse=True)
    a, b, face = _shared_faces(tets)
    # The face opposite corner f holds the simplices of the tet that avoid corner f.
    holds = ~(local[None, :, :] == np.arange(4)[:, None, None]).any(axis=2)  # (4, k)
    row_parts, col_parts = [np.empty(0, dtype=np.int64)], [np.empty(0, dtype=np.int64)]
    for f in range(4):
        on = face == f
        for s in np.flatnonzero(holds[f]):
            ia = a[on] * k + s
            candidates = b[on, None] * k + np.arange(k)[None, :]
            match = key[candidates] == key[ia][:, None]
            row_parts.append(ia)
            col_parts.append(candidates[np.arange(len(ia)), match.argmax(axis=1)])
    rows, cols = np.concatenate(row_parts), np.concatenate(col_parts)
    graph = sp.csr_matrix((np.ones(len(rows), dtype=np.int8), (rows, cols)), shape=(n * k, n * k))
    _, group = connected_components(graph, directed=False)
    return keys, key, group


def _pinched(tets: np.ndarray, local: np.ndarray) -> np.ndarray:
    """The simplices whose tets fall into more than one group (see `star_groups`)."""
    keys, key, group = star_groups(tets, local)
    pairs = unique_rows(np.stack([key, group], axis=1))
    return keys[np.bincount(pairs[:, 0], minlength=len(keys)) > 1]


def pinched_vertices(tets: np.ndarray) -> np.ndarray:
    """Vertices (indices) whose tets fall into groups joined only at the vertex."""
    return _pinched(tets, np.arange(4)[:, None]).ravel()


def pinched_edges(tets: np.ndarray) -> np.ndarray:
    """Edges (E, 2) whose tets fall into groups joined only along the edge."""
    return _pinched(tets, TET_EDGES)


def non_manifold_edges(faces: np.ndarray) -> np.ndarray:
    """Edges (E, 2) of a triangle surface used by other than two of its triangles."""
    edges = np.sort(faces[:, [[0, 1], [1, 2], [2, 0]]].reshape(-1, 2), axis=1)
    unique, counts = unique_rows(edges, return_counts=True)
    return unique[counts != 2]


def boundary_fans(faces: np.ndarray) -> np.ndarray:
    """Fan label (3F,) of each corner incidence (face f, corner c) = 3 f + c of a triangle surface:
    the corners of one vertex share a label when their triangles are joined through edges at it."""
    n = len(faces)
    # Each edge (corner c → c+1) joins its two ends to the same ends in the triangle across it.
    ends = np.stack([np.arange(3), (np.arange(3) + 1) % 3], axis=1)  # (3 edges, 2 corners)
    edges = faces[:, ends].reshape(-1, 2)
    incidence = (3 * np.arange(n)[:, None, None] + ends[None]).reshape(-1, 2)
    flipped = edges[:, 0] > edges[:, 1]
    key = np.sort(edges, axis=1)
    incidence = np.where(flipped[:, None], incidence[:, ::-1], incidence)  # incidences of (smaller, larger)
    order = np.lexsort(key.T[::-1])
    same = np.flatnonzero(np.all(key[order][1:] == key[order][:-1], axis=1))
    i, j = incidence[order[same]], incidence[order[same + 1]]
    rows, cols = np.concatenate([i[:, 0], i[:, 1]]), np.concatenate([j[:, 0], j[:, 1]])
    graph = sp.csr_matrix((np.ones(len(rows), dtype=np.int8), (rows, cols)), shape=(3 * n, 3 * n))
    return connected_components(graph, directed=False)[1]


def non_manifold_vertices(faces: np.ndarray) -> np.ndarray:
    """Vertices of a triangle surface whose triangles form more than one fan (joined through edges)."""
    pairs = unique_rows(np.stack([faces.ravel(), boundary_fans(faces)], axis=1))
    return np.flatnonzero(np.bincount(pairs[:, 0]) > 1)


def hold_width(points: np.ndarray) -> float:
    """Smallest height (m) of a large triangle spanned by held points (P, 3); 0 if fewer than three.

    The triangle: the two points farthest apart (from the one farthest from the
    centroid, the one farthest from it) and the point farthest from the line
    through them. Its smallest height is the height over its longest side.
    """
    if len(points) < 3:
        return 0.0
    a = points[np.argmax(np.linalg.norm(points - points.mean(axis=0), axis=1))]
    b = points[np.argmax(np.linalg.norm(points - a, axis=1))]
    axis = (b - a) / max(np.linalg.norm(b - a), 1e-300)
    rel = points - a
    off = np.linalg.norm(rel - np.outer(rel @ axis, axis), axis=1)
    c = points[np.argmax(off)]
    sides = np.linalg.norm([b - a, c - b, a - c], axis=1)
    area2 = np.linalg.norm(np.cross(b - a, c - a))
    return float(area2 / max(sides.max(), 1e-300))
