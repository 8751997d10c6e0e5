"""Static equilibrium K u = f with prescribed (e.g. bone-attached) dofs, factored once.

Splitting dofs into free (f) and constrained (c) ones, K_ff u_f = f_f - K_fc u_c.
The factorization of K_ff is kept, so quasi-static sequences (a muscle
contracting step by step, the skeleton moving) cost one solve per load.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from hitogata.errors import HitogataError
from hitogata.fem.dofs import constrained_dofs
from hitogata.fem.factor import factorize
from hitogata.options import FactorMethod


class StaticSolver:
    """K factored on its free dofs; ``solve`` returns full displacement vectors (n_dofs,)."""

    def __init__(self, K: sp.spmatrix, fixed_nodes: np.ndarray | list[int] | None = None,
                 fixed_dofs: np.ndarray | list[int] | None = None, method: FactorMethod = "auto") -> None:
        K = sp.csr_matrix(K)
        self.n_dofs = K.shape[0]
        self.fixed = constrained_dofs(self.n_dofs, fixed_nodes, fixed_dofs)
        if len(self.fixed) == 0:
            raise HitogataError("no dof is fixed; allowed: fix at least the 6 dofs that stop rigid-body motion")
        mask = np.ones(self.n_dofs, dtype=bool)
        mask[self.fixed] = False
        self.free = np.flatnonzero(mask)
        rows = K[self.free]
        self._k_fc = rows[:, self.fixed]
        self._solve = factorize(rows[:, self.free], method, node_of_dof=self.free // 3)

    def solve(self, f: np.ndarray, prescribed: np.ndarray | None = None) -> np.ndarray:
        """Displacements for forces f (n_dofs,); constrained dofs take ``prescribed[fixed]`` (default 0)."""
        f = np.asarray(f, dtype=float)
        if f.shape != (self.n_dofs,):
            raise HitogataError(f"force vector has shape {f.shape}; allowed: ({self.n_dofs},)")
        u = np.zeros(self.n_dofs)
        rhs = f[self.free]
        if prescribed is not None:
            u[self.fixed] = np.asarray(prescribed, dtype=float)[self.fixed]
            rhs = rhs - self._k_fc @ u[self.fixed]
        u[self.free] = self._solve(rhs)
        return u


def solve_static(K: sp.spmatrix, f: np.ndarray, fixed_nodes: np.ndarray | list[int] | None = None,
                 fixed_dofs: np.ndarray | list[int] | None = None, prescribed: np.ndarray | None = None,
                 method: FactorMethod = "auto") -> np.ndarray:
    """One-off K u = f with the given nodes and single dofs held (at ``prescribed`` or zero)."""
    return StaticSolver(K, fixed_nodes, fixed_dofs, method).solve(f, prescribed)
