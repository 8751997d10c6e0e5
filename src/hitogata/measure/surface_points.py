"""Points on the skin between its vertices: barycentric landmarks, and paths that start at them.

A landmark found by a ray (acromion, olecranon, ulnar styloid) is the exact
crossing point, kept as barycentric weights of its face's three corners. It
moves continuously as the body's shape changes (a vertex pick jumps by an
edge length — 9–22 mm measured — when the ray moves past the middle of an
edge) and follows the skin into any posture, on any mesh that keeps the
body's vertices first (a subdivided copy, a posed or simulated surface).

Geodesic solvers start paths at vertices, so `insert_points` splits the face
under each point into three, with the point as their shared vertex.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.volume.surface import closest_points_on_triangles

# Barycentric weights are kept at least this far inside a face when the point becomes a
# vertex, so no new triangle is degenerate (moves the point by at most 1e-6 of an edge).
_INSIDE = 1e-6
_CANDIDATES = 16  # triangles with the nearest centroids, whose distance bounds the search


@dataclass(frozen=True)
class SurfacePoint:
    """A point on a face of the body's mesh: its three corner vertices and their weights."""

    corners: tuple[int, int, int]
    weights: tuple[float, float, float]

    def at(self, vertices: np.ndarray) -> np.ndarray:
        """The point (3,) on a surface that shares the body's vertices (rest, posed, subdivided)."""
        return np.asarray(self.weights) @ np.asarray(vertices)[list(self.corners)]

    @classmethod
    def on_face(cls, vertices: np.ndarray, face: np.ndarray, point: np.ndarray) -> SurfacePoint:
        """The point of a triangle (three vertex indices) nearest `point`, as a SurfacePoint."""
        weights = barycentric(vertices[face], point)
        a, b, c = (int(k) for k in face)
        return cls((a, b, c), (float(weights[0]), float(weights[1]), float(weights[2])))


def barycentric(triangle: np.ndarray, point: np.ndarray) -> np.ndarray:
    """Weights (3,) >= 0, summing to 1, of the triangle's (3, 3) point nearest `point`."""
    a, b, c = triangle
    q = closest_points_on_triangles(point[None], a[None], b[None], c[None])[0]
    e1, e2, d = b - a, c - a, q - a
    gram = np.array([[e1 @ e1, e1 @ e2], [e1 @ e2, e2 @ e2]])
    u, v = np.linalg.solve(gram, np.array([d @ e1, d @ e2]))
    weights = np.clip(np.array([1.0 - u - v, u, v]), 0.0, None)
    return weights / weights.sum()


def _nearest_face(corners: np.ndarray, point: np.ndarray) -> int:
    """The triangle (of corners (F, 3, 3)) nearest a point: exact distances only to the
    triangles that can beat the best of the few whose centroids are nearest."""
    centre = corners.mean(axis=1)
    radius = np.linalg.norm(corners - centre[:, None], axis=2).max(axis=1)
    gap = np.linalg.norm(centre - point, axis=1)

    def distances(rows: np.ndarray) -> np.ndarray:
        q = closest_points_on_triangles(np.repeat(point[None], len(rows), axis=0),
                                        corners[rows, 0], corners[rows, 1], corners[rows, 2])
        return np.linalg.norm(q - point, axis=1)

    first = np.argpartition(gap, min(_CANDIDATES, len(gap) - 1))[:_CANDIDATES]
    rows = np.flatnonzero(gap - radius <= distances(first).min())
    return int(rows[np.argmin(distances(rows))])


def insert_points(vertices: np.ndarray, faces: np.ndarray, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The surface with each point (P, 3) made a vertex: its nearest face split in three.

    Returns the new vertices (the old ones first), faces, and the vertex index (P,) of each
    point. A point on a vertex (within round-off) is that vertex.
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    new_vertices, new_faces, indices = [vertices], faces.copy(), []
    count = len(vertices)
    for point in np.asarray(points, dtype=np.float64).reshape(-1, 3):
        corners = np.concatenate(new_vertices)[new_faces]
        face = _nearest_face(corners, point)
        weights = barycentric(corners[face], point)
        if weights.max() > 1.0 - 1e-9:
            indices.append(int(new_faces[face, np.argmax(weights)]))
            continue
        weights = np.maximum(weights, _INSIDE)
        weights /= weights.sum()
        a, b, c = new_faces[face]
        new_vertices.append((weights @ corners[face])[None])
        new_faces = np.concatenate([np.delete(new_faces, face, axis=0),
                                    [[a, b, count], [b, c, count], [c, a, count]]])
        indices.append(count)
        count += 1
    return np.concatenate(new_vertices), new_faces, np.array(indices, dtype=np.int64)
