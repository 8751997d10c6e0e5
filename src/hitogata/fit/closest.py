"""Closest points on a triangle surface: the face and barycentric coordinates of each.

The candidates of a point are the triangles whose centroids are its k nearest
(a `scipy.spatial.cKDTree` over the centroids), each tested exactly
(`hitogata.volume.surface.closest_points_on_triangles`); on a body surface
with even triangles k = 8 finds the true nearest triangle.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from hitogata.volume.surface import closest_points_on_triangles

BLOCK = 20_000  # points per block: bounds the (block·k, 3) intermediates


@dataclass(frozen=True)
class Closest:
    """For each query point: distance, nearest face, barycentric coordinates there, the point itself."""

    distance: np.ndarray  # (P,)
    face: np.ndarray  # (P,)
    bary: np.ndarray  # (P, 3)
    point: np.ndarray  # (P, 3)


def barycentric(p: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """(P, 3) barycentric coordinates of points p lying on triangles (a, b, c)."""
    v0, v1, v2 = b - a, c - a, p - a
    d00, d01, d11 = (v0 * v0).sum(1), (v0 * v1).sum(1), (v1 * v1).sum(1)
    d20, d21 = (v2 * v0).sum(1), (v2 * v1).sum(1)
    den = np.where(np.abs(d00 * d11 - d01 * d01) > 0, d00 * d11 - d01 * d01, 1.0)
    v = (d11 * d20 - d01 * d21) / den
    w = (d00 * d21 - d01 * d20) / den
    return np.clip(np.stack([1.0 - v - w, v, w], axis=1), 0.0, 1.0)


class SurfaceQuery:
    """A fixed triangle surface prepared for closest-point queries (its centroid tree built once)."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray) -> None:
        self.vertices, self.faces = vertices, faces
        self.tri = vertices[faces]
        self.tree = cKDTree(self.tri.mean(axis=1))

    def closest(self, points: np.ndarray, k: int = 8) -> Closest:
        """The closest point of the surface to each of `points` (P, 3)."""
        tri = self.tri
        k = min(k, len(tri))
        n = len(points)
        dist, face, near_point = np.empty(n), np.empty(n, dtype=np.int64), np.empty((n, 3))
        step = max(1, BLOCK // k)
        for s in range(0, n, step):
            p = points[s:s + step]
            _, near = self.tree.query(p, k=k)
            near = near.reshape(len(p), k)
            t = tri[near.ravel()]
            q = closest_points_on_triangles(np.repeat(p, k, axis=0), t[:, 0], t[:, 1], t[:, 2]).reshape(len(p), k, 3)
            d = np.linalg.norm(q - p[:, None, :], axis=2)
            best = d.argmin(axis=1)
            rows = np.arange(len(p))
            dist[s:s + step], face[s:s + step], near_point[s:s + step] = d[rows, best], near[rows, best], q[rows, best]
        t = tri[face]
        return Closest(dist, face, barycentric(near_point, t[:, 0], t[:, 1], t[:, 2]), near_point)


def signed_closest(vertices: np.ndarray, faces: np.ndarray, points: np.ndarray) -> tuple[Closest, np.ndarray]:
    """The closest point of the surface (V, 3), (F, 3) to each of `points` (P, 3), and each point's signed
    distance (P,) along the normal of the face it is nearest (positive: outside an outward surface)."""
    near = SurfaceQuery(vertices, faces).closest(points)
    return near, np.einsum("ij,ij->i", face_normals(vertices, faces)[near.face], points - near.point)


def face_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(F, 3) unit face normals (outward on an outward-oriented surface)."""
    tri = vertices[faces]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-20)


def signed_distances(vertices: np.ndarray, faces: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(P,) each point's offset from its closest surface point along that face's normal: positive
    outside an outward-oriented surface, negative inside; never larger than the distance."""
    near = SurfaceQuery(vertices, faces).closest(points)
    return np.einsum("ij,ij->i", face_normals(vertices, faces)[near.face], points - near.point)
