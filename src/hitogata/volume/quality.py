"""Element quality and boundary fidelity of a tetrahedral mesh.

Dihedral angles bound the conditioning of the stiffness matrix and the
interpolation error of linear tets (Shewchuk 2002, "What is a good linear
element?"); inverted tets make it indefinite. Volume and surface distance
against the skin say how faithfully the mesh fills the body.
"""

from __future__ import annotations

import numpy as np

from hitogata.volume.surface import SurfaceIndex

# Outward faces of a positively oriented tet (0, 1, 2, 3), the one opposite vertex k in row k.
TET_FACES = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])
_EDGE_PAIRS = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]


def signed_volumes(nodes: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """Signed volume (T,) of each tet, positive when positively oriented."""
    p = nodes[tets]
    return np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])) / 6.0


def dihedral_angles(nodes: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """The six interior dihedral angles (T, 6) of each tet, radians.

    The angle at the edge shared by the faces opposite vertices i and j is
    π minus the angle between those faces' outward normals.
    """
    p = nodes[tets]
    normals = np.stack([np.cross(p[:, f[1]] - p[:, f[0]], p[:, f[2]] - p[:, f[0]]) for f in TET_FACES], axis=1)
    normals /= np.linalg.norm(normals, axis=2, keepdims=True)
    cos = np.stack([np.einsum("ij,ij->i", normals[:, i], normals[:, j]) for i, j in _EDGE_PAIRS], axis=1)
    return np.pi - np.arccos(np.clip(cos, -1.0, 1.0))


def boundary_faces(tets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Faces (F, 3) used by one tet only, outward-oriented, and the tet (F,) each belongs to."""
    faces = tets[:, TET_FACES].reshape(-1, 3)
    keys = np.sort(faces, axis=1)
    _, inverse, counts = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
    once = counts[inverse.ravel()] == 1
    return faces[once], np.flatnonzero(once) // 4


def interface_faces(tets: np.ndarray, labels: np.ndarray) -> dict[tuple[int, int], np.ndarray]:
    """Faces shared by two tets of different labels, keyed by (smaller label, larger label).

    Each face is oriented outward from the tet with the smaller label.
    """
    faces = tets[:, TET_FACES].reshape(-1, 3)
    owner = np.repeat(np.arange(len(tets)), 4)
    keys = np.sort(faces, axis=1)
    order = np.lexsort(keys.T[::-1])
    keys, faces, owner = keys[order], faces[order], owner[order]
    pair = np.flatnonzero(np.all(keys[1:] == keys[:-1], axis=1))
    first, second = owner[pair], owner[pair + 1]
    la, lb = labels[first], labels[second]
    differ = la != lb
    pair, first, second, la, lb = pair[differ], first[differ], second[differ], la[differ], lb[differ]
    # Orient from the smaller label's side: keep the face as seen from its own tet.
    face = np.where((la < lb)[:, None], faces[pair], faces[pair + 1])
    lo, hi = np.minimum(la, lb), np.maximum(la, lb)
    return {(int(a), int(b)): face[(lo == a) & (hi == b)] for a, b in sorted(set(zip(lo.tolist(), hi.tolist())))}


def surface_distances(nodes: np.ndarray, faces: np.ndarray, reference: SurfaceIndex, reference_points: np.ndarray,
                      mesh_surface: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Distances between a mesh's boundary and a reference surface, both ways.

    Forward: the vertices, edge midpoints and centroids of `faces` to the
    reference. Backward: `reference_points` (e.g. the skin vertices of the meshed
    part) to `mesh_surface` (default `faces`). The max over both is a sampled
    Hausdorff distance.
    """
    tri = nodes[faces]
    samples = np.concatenate([nodes[np.unique(faces)], tri.mean(axis=1),
                              0.5 * (tri + np.roll(tri, 1, axis=1)).reshape(-1, 3)])
    forward = reference.distance(samples)
    target = faces if mesh_surface is None else mesh_surface
    backward = SurfaceIndex(nodes, target).distance(reference_points) if len(reference_points) else np.empty(0)
    return forward, backward
