"""The solid to mesh: the whole body inside its skin, or the trunk cut from it.

The trunk is the body between two horizontal planes — the base of the neck
(head of rig bone `neck01`, about C7/T1) and the hip joint centres (heads of
`upperleg01.L/R`) — without the arms. The arms are cut off along the surface
of equal "power distance" to the arm bones and to the trunk bones: a point
belongs to the arm when (distance to the nearest arm bone − arm radius) is
smaller than (distance to the nearest trunk bone − trunk radius). Each radius
is the median distance from its bones to the skin vertices the skinning
weights give mostly to them, so the cut follows this body's own girths and
runs through the armpit and over the shoulder joint.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np
import scipy.sparse as sp

from hitogata.volume.anatomy import ARM_PREFIXES, TRUNK_BONES
from hitogata.volume.domain import HalfSpace, ImplicitDomain, Intersection, SurfaceDomain


class RigLike(Protocol):
    """Bone names with head and tail positions (m): `hitogata.body.rig.Rig` is one."""

    @property
    def names(self) -> tuple[str, ...]: ...
    @property
    def heads(self) -> np.ndarray: ...
    @property
    def tails(self) -> np.ndarray: ...


def segment_distance(points: np.ndarray, heads: np.ndarray, tails: np.ndarray) -> np.ndarray:
    """Distance (P, S) from each point to each segment head→tail."""
    d = tails - heads
    length2 = np.maximum(np.einsum("sk,sk->s", d, d), 1e-30)
    out = np.empty((len(points), len(heads)))
    step = max(1, (1 << 20) // max(1, len(heads)))
    for s in range(0, len(points), step):
        rel = points[s:s + step, None, :] - heads[None]
        t = np.clip(np.einsum("psk,sk->ps", rel, d) / length2, 0.0, 1.0)
        out[s:s + step] = np.linalg.norm(rel - t[..., None] * d[None], axis=2)
    return out


@dataclass(frozen=True)
class TrunkLandmarks:
    """Trunk landmarks of a rig at rest: the spine polyline, hip and shoulder joints, neck base."""

    spine: np.ndarray  # (K, 3) from the pelvis joint up to the base of the neck
    hips: np.ndarray  # (2, 3) hip joint centres, left then right
    knees_dir: np.ndarray  # (2, 3) unit vectors down each thigh
    shoulders: np.ndarray  # (2, 3) shoulder joint centres
    arms_dir: np.ndarray  # (2, 3) unit vectors down each upper arm

    @classmethod
    def from_rig(cls, rig: RigLike) -> "TrunkLandmarks":
        def head(n: str) -> np.ndarray:
            return np.asarray(rig.heads[rig.names.index(n)], dtype=np.float64)

        def direction(n: str) -> np.ndarray:
            d = rig.tails[rig.names.index(n)] - rig.heads[rig.names.index(n)]
            return d / np.linalg.norm(d)

        spine = np.array([head(n) for n in ("spine05", "spine04", "spine03", "spine02", "spine01", "neck01")])
        return cls(
            spine=spine,
            hips=np.array([head("upperleg01.L"), head("upperleg01.R")]),
            knees_dir=np.array([direction("upperleg01.L"), direction("upperleg01.R")]),
            shoulders=np.array([head("upperarm01.L"), head("upperarm01.R")]),
            arms_dir=np.array([direction("upperarm01.L"), direction("upperarm01.R")]),
        )

    @property
    def hip_height(self) -> float:
        return float(self.hips[:, 1].mean())

    @property
    def neck_height(self) -> float:
        return float(self.spine[-1, 1])

    @property
    def hip_width(self) -> float:
        return float(np.linalg.norm(self.hips[0] - self.hips[1]))

    def level(self, y: np.ndarray) -> np.ndarray:
        """Height as a fraction s of the span hip joints (0) → base of the neck (1)."""
        return (y - self.hip_height) / (self.neck_height - self.hip_height)

    def spine_at(self, y: np.ndarray) -> np.ndarray:
        """(P, 3) point of the spine polyline at each height (clamped at its ends)."""
        order = np.argsort(self.spine[:, 1])
        s = self.spine[order]
        return np.stack([np.interp(y, s[:, 1], s[:, k]) for k in range(3)], axis=1)

    def spine_axis_at(self, y: np.ndarray) -> np.ndarray:
        """(P, 3) unit tangent of the spine polyline, pointing up, at each height."""
        segment = np.clip(np.searchsorted(self.spine[:, 1], y) - 1, 0, len(self.spine) - 2)
        d = self.spine[segment + 1] - self.spine[segment]
        return d / np.linalg.norm(d, axis=1, keepdims=True)


def _group_radius(skin: np.ndarray, weights: sp.csr_matrix, columns: list[int],
                  heads: np.ndarray, tails: np.ndarray) -> float:
    """Median distance from a bone group to the skin vertices weighted mostly to it."""
    share = np.asarray(weights[:, columns].sum(axis=1)).ravel()
    owned = skin[share > 0.5]
    return float(np.median(segment_distance(owned, heads, tails).min(axis=1)))


def arm_separator(rig: RigLike, skin: np.ndarray, weights: sp.csr_matrix):
    """f(points) < 0 on the trunk side of the trunk/arm power-distance surface (see module note)."""
    arm = [i for i, n in enumerate(rig.names) if n.startswith(ARM_PREFIXES)]
    trunk = [rig.names.index(n) for n in TRUNK_BONES]
    heads, tails = np.asarray(rig.heads, dtype=np.float64), np.asarray(rig.tails, dtype=np.float64)
    r_arm = _group_radius(skin, weights, arm, heads[arm], tails[arm])
    r_trunk = _group_radius(skin, weights, trunk, heads[trunk], tails[trunk])

    def f(points: np.ndarray) -> np.ndarray:
        d_trunk = segment_distance(points, heads[trunk], tails[trunk]).min(axis=1) - r_trunk
        d_arm = segment_distance(points, heads[arm], tails[arm]).min(axis=1) - r_arm
        return d_trunk - d_arm

    return f


def trunk_domain(vertices: np.ndarray, faces: np.ndarray, rig: RigLike,
                 weights: sp.csr_matrix) -> tuple[Intersection, tuple[np.ndarray, np.ndarray]]:
    """The trunk as a domain (parts: skin, neck, hips, arms) and a box that holds it."""
    marks = TrunkLandmarks.from_rig(rig)
    up = np.array([0.0, 1.0, 0.0])
    neck = HalfSpace(np.array([0.0, marks.neck_height, 0.0]), up, "neck")
    hips = HalfSpace(np.array([0.0, marks.hip_height, 0.0]), -up, "hips")
    arms = ImplicitDomain(arm_separator(rig, vertices, weights), "arms")
    domain = Intersection(SurfaceDomain(vertices, faces, "skin"), neck, hips, arms)
    part = vertices[neck.contains(vertices) & hips.contains(vertices) & arms.contains(vertices)]
    pad = 0.01
    lo, hi = part.min(axis=0) - pad, part.max(axis=0) + pad
    lo[1], hi[1] = marks.hip_height - pad, marks.neck_height + pad
    return domain, (lo, hi)


def body_domain(vertices: np.ndarray, faces: np.ndarray) -> tuple[SurfaceDomain, tuple[np.ndarray, np.ndarray]]:
    """The whole body inside its skin, and its bounding box."""
    return SurfaceDomain(vertices, faces, "skin"), (vertices.min(axis=0), vertices.max(axis=0))
