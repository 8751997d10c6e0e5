"""Display surfaces of a tet mesh labelled by region: the boundary of a union of regions, smoothed.

Regions are labelled per tetrahedron, so their boundaries are staircases of
lattice faces; for pictures and the viewer they are smoothed with Taubin's
λ|μ filter (G. Taubin, "A signal processing approach to fair surface design",
SIGGRAPH 1995), which, unlike plain Laplacian smoothing, does not shrink them.
The meshes themselves are never changed.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp

from hitogata.geometry.tets import boundary_faces

TAUBIN = (0.5, -0.53)  # λ (smooth) then μ (inflate back): the pass band of Taubin's paper


def region_boundary(tets: np.ndarray, region: np.ndarray, names: Sequence[str], chosen: Sequence[str],
                    held_bone: np.ndarray | None = None) -> np.ndarray:
    """Outward boundary triangles (F, 3) of the union of the `chosen` regions' tets (`region` (T,)
    indexes `names`); `held_bone`, the soft tissue's faces on bones held outside the mesh, is the
    bone's surface when "bone" is chosen."""
    within = np.isin(region, [names.index(name) for name in chosen if name in names])
    faces = boundary_faces(np.asarray(tets)[within])[0] if within.any() else np.empty((0, 3), dtype=np.int64)
    if "bone" in chosen and held_bone is not None and len(held_bone):
        faces = np.concatenate([faces, held_bone])
    return faces


def smoothing_operator(n: int, faces: np.ndarray) -> sp.csr_matrix:
    """(n, n) one averaging step over the faces' edges: the mean of a vertex's neighbours minus the
    vertex, on the faces' vertices; 0 on the other points (they stay). Built once per surface."""
    faces = np.asarray(faces)
    used = np.zeros(n, dtype=bool)
    used[faces.ravel()] = True
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    adjacency = sp.csr_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
    adjacency = ((adjacency + adjacency.T) > 0).astype(np.float64)
    degree = np.maximum(np.asarray(adjacency.sum(axis=1)).ravel(), 1.0)
    return (sp.diags(used / degree) @ adjacency - sp.diags(used.astype(np.float64))).tocsr()


def taubin_smooth(points: np.ndarray, faces: np.ndarray, iterations: int,
                  operator: sp.csr_matrix | None = None) -> np.ndarray:
    """(N, 3) points with the vertices of `faces` moved by `iterations` λ|μ passes over the faces'
    edges (each vertex towards, then away from, the mean of its neighbours); other points stay.
    `operator`: `smoothing_operator(N, faces)`, when the same surface is smoothed again and again."""
    points = np.asarray(points, dtype=np.float64)
    operator = smoothing_operator(len(points), faces) if operator is None else operator
    out = points.copy()
    for _ in range(iterations):
        for factor in TAUBIN:
            out += factor * (operator @ out)
    return out
