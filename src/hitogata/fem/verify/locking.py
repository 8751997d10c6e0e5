"""How results depend on Poisson's ratio as tissue approaches incompressibility (nu -> 0.5).

Linear tets "lock": a P1 displacement field can hardly bend without changing
volume, so as the bulk modulus grows relative to shear the mesh becomes far
too stiff. Quadratic tets have enough freedom to bend at constant volume and
lock much later, but still some; on each element's mean dilatation
(`stiffness_matrix(..., dilatation="mean")`) they do not lock at all.
``poisson_sweep`` measures this on any mesh so the choice of element is made
with numbers: for a cantilever, beam theory says the bending frequency barely
depends on nu, so any rise is the element's artefact.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.fem.assembly import mass_matrix, sparsity, stiffness_matrix
from hitogata.fem.elements import lift_node_set, p2_mesh
from hitogata.fem.modes import solve_modes
from hitogata.options import Dilatation


@dataclass(frozen=True)
class PoissonSweep:
    """Frequency (Hz) of one mode per Poisson's ratio, for P1, P2 and P2 on the mean dilatation, on the same mesh."""

    nus: np.ndarray
    p1: np.ndarray
    p2: np.ndarray
    p2_mean: np.ndarray

    def table(self) -> str:
        """Plain-text table: nu, each element's frequency and its change from the first nu."""
        lines = ["    nu    P1 f (Hz)  change   P2 f (Hz)  change  P2 mean-dil.  change"]
        for nu, f1, f2, f3 in zip(self.nus, self.p1, self.p2, self.p2_mean):
            lines.append(f"{nu:7.4f}  {f1:9.5f}  {f1 / self.p1[0] - 1:+7.2%}  {f2:9.5f}  {f2 / self.p2[0] - 1:+7.2%}"
                         f"  {f3:9.5f}  {f3 / self.p2_mean[0] - 1:+7.2%}")
        return "\n".join(lines)


def poisson_sweep(points: np.ndarray, tets: np.ndarray, fixed_nodes: np.ndarray, E: float, rho: float,
                  nus: np.ndarray | list[float], mode: int = 0) -> PoissonSweep:
    """Frequency of mode ``mode`` (0 = lowest) for each nu, on a P1 mesh and on its P2 refinement
    (with the volumetric term integrated in full, and on the mean dilatation).

    fixed_nodes are indices into the P1 mesh; on the P2 mesh the midpoints
    between fixed nodes are fixed as well.
    """
    points = np.asarray(points, dtype=float)
    tets = np.asarray(tets)
    nus = np.asarray(nus, dtype=float)
    points2, tets2 = p2_mesh(points, tets)
    fixed2 = lift_node_set(tets2, fixed_nodes)
    out = []
    cases: tuple[tuple[np.ndarray, np.ndarray, np.ndarray, Dilatation], ...] = (
        (points, tets, fixed_nodes, "full"), (points2, tets2, fixed2, "full"), (points2, tets2, fixed2, "mean"))
    for pts, tt, fixed, dilatation in cases:
        pattern = sparsity(tt, len(pts))
        M = mass_matrix(pts, tt, rho, pattern=pattern)
        freqs = [solve_modes(stiffness_matrix(pts, tt, E, nu, pattern, dilatation), M, mode + 1,
                             fixed).frequencies[mode] for nu in nus]
        out.append(np.array(freqs))
    return PoissonSweep(nus, *out)
