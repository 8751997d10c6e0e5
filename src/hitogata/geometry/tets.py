"""Topology of a tetrahedral mesh: faces, boundary, face adjacency and signed volumes.

The one place these are defined; the mesher (volume), the finite elements
(fem, elastic), the simulation (dynamics) and the viewer use them. Tets are
(T, 4) corner indices, or (T, 10) quadratic tets whose first four columns are
the corners (only the corners matter here). A tet (0, 1, 2, 3) is positively
oriented when (p1 − p0) · ((p2 − p0) × (p3 − p0)) > 0.
"""

from __future__ import annotations

import numpy as np

from hitogata.geometry.unique import unique_rows

#: The face opposite each corner (row k: opposite corner k), outward-oriented for a positive tet.
TET_FACES = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])


def tet_faces(tets: np.ndarray) -> np.ndarray:
    """(4T, 3) every tet's four faces, outward-oriented; face 4t + k is tet t's face opposite corner k."""
    return np.asarray(tets)[:, :4][:, TET_FACES].reshape(-1, 3)


def on_boundary(tets: np.ndarray) -> np.ndarray:
    """(4T,) which of `tet_faces(tets)` belong to one tet only."""
    keys = np.sort(tet_faces(tets), axis=1)
    _, inverse, counts = unique_rows(keys, return_inverse=True, return_counts=True)
    return counts[inverse] == 1


def boundary_faces(tets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Faces (F, 3) used by one tet only, outward-oriented, and the tet (F,) each belongs to."""
    once = on_boundary(tets)
    return tet_faces(tets)[once], np.flatnonzero(once) // 4


def shared_face_pairs(tets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The faces two tets share, as index pairs (P,), (P,) into `tet_faces(tets)` (4t + k: tet t's
    face opposite its corner k), one from each tet."""
    keys = np.sort(tet_faces(tets), axis=1)
    order = np.lexsort(keys.T[::-1])
    shared = np.flatnonzero(np.all(keys[order][1:] == keys[order][:-1], axis=1))
    return order[shared], order[shared + 1]


def face_neighbours(tets: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Pairs of tets sharing a face: tets a (P,), b (P,), and the shared face (P, 3) as seen from a and from b."""
    first, second = shared_face_pairs(tets)
    faces = tet_faces(tets)
    return first // 4, second // 4, faces[first], faces[second]


def signed_volumes(nodes: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """Signed volume (T,) of each tet, positive when positively oriented."""
    p = np.asarray(nodes)[np.asarray(tets)[:, :4]]
    return np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])) / 6.0
