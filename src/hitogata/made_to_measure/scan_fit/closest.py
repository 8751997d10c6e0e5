"""Closest points on a triangle surface: the face and barycentric coordinates of each.

The candidates of a point are the triangles whose centroids are its k nearest
(a `scipy.spatial.cKDTree` over the centroids), each tested exactly
(`hitogata.geometry.closest.nearest_on_triangles`); on a body surface
with even triangles k = 8 finds the true nearest triangle.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from hitogata.geometry.closest import barycentric_on_triangles, nearest_on_triangles
from hitogata.geometry.normals import face_normals


@dataclass(frozen=True)
class Closest:
    """For each query point: distance, nearest face, barycentric coordinates there, the point itself."""

    distance: np.ndarray  # (P,)
    face: np.ndarray  # (P,)
    bary: np.ndarray  # (P, 3)
    point: np.ndarray  # (P, 3)


class SurfaceQuery:
    """A fixed triangle surface prepared for closest-point queries (its centroid tree built once)."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray) -> None:
        self.vertices, self.faces = vertices, faces
        self.tri = vertices[faces]
        self.tree = cKDTree(self.tri.mean(axis=1))

    def closest(self, points: np.ndarray, k: int = 8) -> Closest:
        """The closest point of the surface to each of `points` (P, 3)."""
        dist, face, point = nearest_on_triangles(self.tree, self.tri, points, k)
        return Closest(dist, face, barycentric_on_triangles(point, self.tri[face]), point)


def signed_closest(vertices: np.ndarray, faces: np.ndarray, points: np.ndarray) -> tuple[Closest, np.ndarray]:
    """The closest point of the surface (V, 3), (F, 3) to each of `points` (P, 3), and each point's signed
    distance (P,) along the normal of the face it is nearest (positive: outside an outward surface)."""
    near = SurfaceQuery(vertices, faces).closest(points)
    return near, np.einsum("ij,ij->i", face_normals(vertices, faces)[near.face], points - near.point)


def signed_distances(vertices: np.ndarray, faces: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(P,) each point's offset from its closest surface point along that face's normal: positive
    outside an outward-oriented surface, negative inside; never larger than the distance."""
    return signed_closest(vertices, faces, points)[1]
