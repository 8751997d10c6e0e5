"""Scans made from our own bodies, perturbed as real scans are: for the tests and the benchmark.

A body (posed or at rest) becomes a point cloud sampled evenly over its skin,
or a triangle mesh of a different triangulation (each triangle split in four,
the vertices slid along the surface); then scanner noise along every axis,
holes where a scanner does not see (under the arms, between the legs), a rigid
offset, and the unit of the file.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.body.model import Body
from hitogata.geometry.normals import vertex_normals
from hitogata.made_to_measure.scan_fit.register import rotation_vector
from hitogata.made_to_measure.scan_fit.scan import UNITS, Scan
from hitogata.measure.landmarks import body_landmarks

HOLE_RADIUS = 0.05  # m
ARMPIT_DROP = 0.08  # m below the shoulder joint: where the armpit's hole is centred


@dataclass(frozen=True)
class Perturbation:
    """How a synthetic scan differs from the body: noise (m, per axis), a rigid offset, the file's unit,
    holes, and a fraction of its points dropped at random (a mesh loses their triangles)."""

    noise: float = 0.0015
    rotation: tuple[float, float, float] = (0.1, 0.6, -0.05)  # rotation vector, radians
    translation: tuple[float, float, float] = (0.25, 0.1, -0.3)  # m
    unit: str = "mm"
    holes: bool = True
    dropped: float = 0.0


def hole_centres(body: Body, vertices: np.ndarray, joints: np.ndarray) -> np.ndarray:
    """(3, 3) the armpits (skin nearest a point below each shoulder joint) and the crotch, in the posture."""
    names = body.rig.names
    armpits = [joints[names.index(f"upperarm01.{side}")] - np.array([0.0, ARMPIT_DROP, 0.0]) for side in "LR"]
    nearest = [int(np.argmin(np.linalg.norm(vertices - p, axis=1))) for p in armpits]
    return vertices[[*nearest, body_landmarks(body).crotch]]


def _split(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each triangle split in four at its edge midpoints (shared midpoints merged)."""
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    unique, index = np.unique(edges, axis=0, return_inverse=True)
    mid = len(vertices) + index.reshape(3, -1).T  # (F, 3): midpoints of edges 01, 12, 20
    points = np.vstack([vertices, 0.5 * (vertices[unique[:, 0]] + vertices[unique[:, 1]])])
    a, b, c = faces.T
    m01, m12, m20 = mid.T
    new = np.concatenate([np.stack([a, m01, m20], 1), np.stack([m01, b, m12], 1), np.stack([m20, m12, c], 1),
                          np.stack([m01, m12, m20], 1)])
    return points, new


def synthetic_scan(body: Body, vertices: np.ndarray, joints: np.ndarray, perturbation: Perturbation = Perturbation(),
                   points: int | None = 100_000, seed: int = 0) -> tuple[np.ndarray, np.ndarray | None]:
    """Scan points (in the file's unit) and triangles (None for a cloud) of the body in a posture.

    `vertices` (V, 3), `joints` (B, 3): the body's skin and rig joints in the posture.
    `points`: a cloud of that many points; None: a mesh of a different triangulation.
    """
    rng = np.random.default_rng(seed)
    faces = body.faces
    if points is None:
        cloud, tris = _split(vertices, faces)
        normals = vertex_normals(cloud, tris)
        slide = rng.normal(0.0, 0.002, cloud.shape)
        cloud = cloud + slide - np.einsum("ij,ij->i", slide, normals)[:, None] * normals
    else:
        cloud, tris = Scan(vertices, faces, "m").sample(points, seed), None
    seen = rng.random(len(cloud)) >= perturbation.dropped if perturbation.dropped else np.ones(len(cloud), bool)
    if perturbation.holes:
        centres = hole_centres(body, vertices, joints)
        seen &= np.min(np.linalg.norm(cloud[:, None, :] - centres[None], axis=2), axis=1) > HOLE_RADIUS
    if tris is not None:
        tris = tris[seen[tris].all(axis=1)]
    else:
        cloud = cloud[seen]
    cloud = cloud + rng.normal(0.0, perturbation.noise, cloud.shape)
    cloud = cloud @ rotation_vector(np.asarray(perturbation.rotation)).T + np.asarray(perturbation.translation)
    return cloud / UNITS[perturbation.unit], tris
