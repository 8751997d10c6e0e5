"""Lowest vibration modes of K phi = lambda M phi with Dirichlet (bone) nodes.

Fixed dofs are removed from the system (their displacement is zero in the
mode shapes); the remaining generalized eigenproblem is solved by
shift-invert Lanczos (ARPACK through scipy's ``eigsh``) around ``sigma``, with
K - sigma M factored by SuperLU on a nested-dissection ordering
(``factor.py``), or densely on request (small systems, cross-checks).
Modes are mass-normalised: Phi^T M Phi = I, Phi^T K Phi = diag(lambda), and
lambda = omega^2, so f = sqrt(lambda) / 2 pi Hz.
"""

from __future__ import annotations

from contextlib import nullcontext
from dataclasses import dataclass

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from hitogata.errors import HitogataError
from hitogata.fem.dofs import free_dofs
from hitogata.fem.factor import factorize
from hitogata.options import EIGEN_SOLVERS as SOLVERS, EigenSolver



@dataclass(frozen=True)
class Modes:
    """Eigenvalues lambda (k,) ascending, in (rad/s)^2, and mass-normalised shapes (n_dofs, k)."""

    eigenvalues: np.ndarray
    vectors: np.ndarray

    @property
    def frequencies(self) -> np.ndarray:
        """Natural frequencies in Hz."""
        return frequencies_hz(self.eigenvalues)


def no_modes(n_nodes: int) -> Modes:
    """No modes of a model of `n_nodes` nodes: what a model built for held postures carries (statics need
    none, and the shift-invert factor they would take is half the model's build)."""
    return Modes(np.zeros(0), np.zeros((3 * n_nodes, 0)))


def frequencies_hz(eigenvalues: np.ndarray) -> np.ndarray:
    """sqrt(lambda) / 2 pi, with round-off negatives (rigid-body modes) read as 0 Hz."""
    return np.sqrt(np.maximum(np.asarray(eigenvalues, dtype=float), 0.0)) / (2.0 * np.pi)


def solve_modes(K: sp.spmatrix, M: sp.spmatrix, n_modes: int, fixed_nodes: np.ndarray | list[int] | None = None,
                solver: EigenSolver = "auto", sigma: float | None = None, tol: float = 1e-10,
                blas_threads: int | None = 1) -> Modes:
    """The ``n_modes`` lowest modes of (K, M) with the dofs of ``fixed_nodes`` held at zero.

    solver: "auto" (= "superlu-nd", see factor.py), "dense" (LAPACK
    on full matrices: small systems and cross-checks), "scipy" (eigsh's own
    shift-invert with SuperLU/COLAMD: the baseline), "superlu-nd" or
    "pardiso" (eigsh with our factorization of K - sigma M).
    sigma: shift; default 0 when nodes are fixed (K then positive definite),
    else a small negative value below the rigid-body modes.
    tol: ARPACK's relative residual tolerance (0 = machine precision); the
    eigenvalues' error is of order tol^2, far below any modelling error.
    blas_threads: OpenBLAS threads while ARPACK runs (needs threadpoolctl;
    None leaves them alone). ARPACK's work is memory-bound matrix-vector BLAS,
    which extra threads do not speed up but, when the cores are shared, slow
    down several-fold (docs/decisions/0008-blas-on-one-thread-in-small-solves.md).
    """
    K = sp.csr_matrix(K)
    M = sp.csr_matrix(M)
    if K.shape != M.shape or K.shape[0] != K.shape[1]:
        raise HitogataError(f"K {K.shape} and M {M.shape} must be square and of the same size")
    if solver not in SOLVERS:
        raise HitogataError(f"eigen solver {solver!r} is unknown; allowed: {', '.join(SOLVERS)}")
    free = free_dofs(K.shape[0], fixed_nodes)
    n_free = len(free)
    most = n_free if solver == "dense" else n_free - 1
    if not 1 <= n_modes <= most:
        raise HitogataError(f"n_modes = {n_modes} is invalid; allowed: 1..{most} "
                            "(all free dofs with solver='dense', one less otherwise)")
    Kf = K[free][:, free]
    Mf = M[free][:, free]
    if sigma is None:
        sigma = 0.0 if n_free < K.shape[0] else -1e-6 * Kf.diagonal().mean() / Mf.diagonal().mean()
    # ARPACK's own start vector comes from a generator it keeps between calls, so the modes of one model
    # differed in their last digits with the calls before them in the process (and a contact's yes/no with them)
    start = np.random.default_rng(0).standard_normal(n_free)
    if solver == "dense":
        lam, vec = la.eigh(Kf.toarray(), Mf.toarray(), subset_by_index=[0, n_modes - 1])
    elif solver == "scipy":
        with _openblas_limit(blas_threads):
            lam, vec = sla.eigsh(Kf, n_modes, Mf, sigma=sigma, which="LM", tol=tol, v0=start)
    else:
        shifted = (Kf - sigma * Mf) if sigma else Kf
        solve = factorize(shifted, solver, node_of_dof=free // 3, positive_definite=sigma <= 0.0)
        op = sla.LinearOperator(Kf.shape, matvec=solve, matmat=solve, dtype=float)
        Mf.eliminate_zeros()  # consistent M shares K's pattern; its matvecs need only a third of it
        with _openblas_limit(blas_threads):
            lam, vec = sla.eigsh(Kf, n_modes, Mf, sigma=sigma, which="LM", OPinv=op, tol=tol, v0=start)

    order = np.argsort(lam)
    lam, vec = lam[order], vec[:, order]
    vec = vec / np.sqrt(np.einsum("ik,ik->k", vec, Mf @ vec))
    pivot = np.abs(vec).argmax(axis=0)
    vec = vec * np.sign(vec[pivot, np.arange(vec.shape[1])])  # deterministic sign
    full = np.zeros((K.shape[0], n_modes))
    full[free] = vec
    return Modes(lam, full)


def _openblas_limit(threads: int | None):
    """A context limiting OpenBLAS threads if threadpoolctl is installed, else doing nothing.

    Only OpenBLAS (numpy's and scipy's BLAS): MKL's threads drive PARDISO and stay free.
    """
    if threads is None:
        return nullcontext()
    try:
        from threadpoolctl import ThreadpoolController
    except ImportError:
        return nullcontext()
    # selected by internal API: a limits dict keyed "openblas" (not a user API, file path or
    # prefix) limits nothing (docs/decisions/0008-blas-on-one-thread-in-small-solves.md)
    return ThreadpoolController().select(internal_api="openblas").limit(limits=threads)
