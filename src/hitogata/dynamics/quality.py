"""How well a posed elastic body keeps its tissue: inversions, region volumes, skin distortion.

Compared on the same pose: plain linear blend skinning of the FE nodes,
dual-quaternion skinning, and the elastic body (DQS + the quasi-static
correction). Measures:

- inverted elements: corner tetrahedra with volume <= 0;
- region volume change: each tissue region's volume against rest;
- skin distortion: on the FE skin faces, the root mean square of the log
  principal stretches sqrt(ln² σ1 + ln² σ2) of each triangle, weighted by
  rest area — 0 for an isometric surface, counting both stretch and
  squeeze (LBS's collapsing joints show up here);
- tissue distortion: the same for the tets' three principal stretches.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from dataclasses import dataclass

import numpy as np

from hitogata.dynamics.motion import BodyDynamics
from hitogata.dynamics.quasistatic import HELD, rotate
from hitogata.dynamics.rigging import node_rig
from hitogata.dynamics.volumes import corner_volumes
from hitogata.geometry.normals import triangle_areas

if TYPE_CHECKING:
    from hitogata.elastic import ElasticModel

# A held posture's quasi-statics from rest: Chebyshev-accelerated local/global steps (`quasistatic.HELD`),
# at most so many before the floor repairs; the default bodies' 20 extreme poses converge to 0.01 mm in
# 19-206 (docs/decisions/0062-a-held-posture-by-chebyshev-steps.md).
STATIC_ITERATIONS = 500


@dataclass(frozen=True)
class PoseQuality:
    """One posed node set's figures."""

    method: str
    inverted: int
    region_change: dict[str, float]  # relative, per tissue region
    skin_distortion: float
    skin_distortion_max: float
    tissue_distortion: float

    def line(self) -> str:
        regions = ", ".join(f"{k} {v * 100:+.2f}%" for k, v in self.region_change.items())
        return (f"{self.method:8s} inverted {self.inverted:4d}; skin distortion {self.skin_distortion:.4f} "
                f"(max {self.skin_distortion_max:.2f}); tissue {self.tissue_distortion:.4f}; {regions}")


def log_stretches(rest: np.ndarray, posed: np.ndarray) -> np.ndarray:
    """sqrt(Σ ln² σ) per simplex: rest and posed corners (S, k, 3), k = 3 (triangles) or 4 (tets)."""
    a, b = rest[:, 1:] - rest[:, :1], posed[:, 1:] - posed[:, :1]  # (S, k-1, 3) edges
    gram_rest = a @ np.swapaxes(a, 1, 2)
    gram_posed = b @ np.swapaxes(b, 1, 2)
    # principal stretches²: eigenvalues of gram_rest⁻¹ gram_posed (a generalised eigenproblem)
    ev = np.linalg.eigvals(np.linalg.solve(gram_rest, gram_posed)).real
    return np.sqrt((0.25 * np.log(np.maximum(ev, 1e-12)) ** 2).sum(axis=1))


def pose_quality(model: ElasticModel, x: np.ndarray, method: str) -> PoseQuality:
    """Figures of node positions x (N, 3) of an elastic model."""
    rest = model.points
    v0, v = corner_volumes(rest, model.elements), corner_volumes(x, model.elements)
    regions = {name: float(v[model.region == k].sum() / v0[model.region == k].sum() - 1.0)
               for k, name in enumerate(model.region_names) if np.any(model.region == k)}
    faces = model.volume.boundary_faces[model.volume.boundary_on_skin]
    tri0 = rest[faces]
    area = triangle_areas(tri0)
    skin = log_stretches(tri0, x[faces])
    corners = model.elements[:, :4]
    soft = model.region != model.region_names.index("bone")
    tissue = log_stretches(rest[corners[soft]], x[corners[soft]])
    return PoseQuality(method, int((v <= 0).sum()), regions, float(np.sqrt(np.sum(area * skin**2) / area.sum())),
                       float(skin.max()), float(np.sqrt(np.sum(v0[soft] * tissue**2) / v0[soft].sum())))


def compare_pose(dynamics: BodyDynamics, angles: np.ndarray,
                 iterations: int = STATIC_ITERATIONS) -> dict[str, PoseQuality]:
    """LBS, DQS and the elastic body on one pose (rest-relative angles (D,)), no loads."""
    pose = dynamics.poser.kinematics.pose(angles)
    out = {}
    for method in ("lbs", "dqs"):
        rig = dynamics.rig if dynamics.rig.method == method else node_rig(dynamics.poser, dynamics.model, method, bind_skin=False)
        g, R = rig.pose(pose.rotations, pose.translations)
        out[method] = pose_quality(dynamics.model, g[0], method)
        if rig is dynamics.rig:
            delta, _ = dynamics.quasi_static(g[0], R[0], None, None, iterations, acceleration=HELD)  # from rest
            out["elastic"] = pose_quality(dynamics.model, g[0] + rotate(R[0], delta), "elastic")
    return out
