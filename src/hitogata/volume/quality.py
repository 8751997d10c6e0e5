"""Element quality and boundary fidelity of a tetrahedral mesh.

Dihedral angles bound the conditioning of the stiffness matrix and the
interpolation error of linear tets (Shewchuk 2002, "What is a good linear
element?"); inverted tets make it indefinite. Volume and surface distance
against the skin say how faithfully the mesh fills the body.
"""

from __future__ import annotations

import numpy as np

from hitogata.geometry.tets import TET_FACES, boundary_faces, face_neighbours, signed_volumes
from hitogata.volume.surface import SurfaceIndex

__all__ = ["boundary_faces", "dihedral_angles", "interface_faces", "signed_volumes", "surface_distances"]

_EDGE_PAIRS = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]


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


def interface_faces(tets: np.ndarray, labels: np.ndarray) -> dict[tuple[int, int], np.ndarray]:
    """Faces shared by two tets of different labels, keyed by (smaller label, larger label).

    Each face is oriented outward from the tet with the smaller label.
    """
    first, second, from_first, from_second = face_neighbours(tets)
    la, lb = labels[first], labels[second]
    differ = la != lb
    from_first, from_second, la, lb = from_first[differ], from_second[differ], la[differ], lb[differ]
    # Orient from the smaller label's side: keep the face as seen from its own tet.
    face = np.where((la < lb)[:, None], from_first, from_second)
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
