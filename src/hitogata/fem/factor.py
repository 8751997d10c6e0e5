"""Sparse direct factorizations of symmetric FE matrices, behind one interface.

The modal and static solvers spend their time factoring K (or K - sigma M)
and solving with the factors. Methods:

- ``"superlu-nd"`` (the default, "auto"): scipy's SuperLU on the matrix
  reordered by METIS nested dissection of the node graph (``pymetis``), in
  symmetric mode with diagonal pivots; without pymetis, SuperLU's own
  minimum degree on A + A^T. Factors 2.6x faster than scipy's default with
  half the fill (18k-dof P2 trunk-sized box: 1.1 s vs 2.9 s, 13 M vs 24 M entries).
- ``"pardiso"``: Intel MKL PARDISO through the optional ``pypardiso`` package
  (Cholesky, multithreaded), only if pypardiso and mkl (x86-64, ~0.9 GB) are
  installed. Its factorization is 3-10x faster still, but each solve is no
  faster than SuperLU's and its threads wait on each other when the cores are
  shared, so it wins only where factoring dominates (large static problems),
  not in eigen-solves, which need ~3.5 solves per mode.
- ``"superlu"``: scipy's default (SuperLU with COLAMD, partial pivoting),
  what ``scipy.sparse.linalg.eigsh(sigma=...)`` uses: the baseline.

All give the same solution to round-off.
"""

from __future__ import annotations

from collections.abc import Callable

from typing import cast

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from hitogata.errors import HitogataError
from hitogata.options import FACTOR_METHODS as METHODS, FactorMethod

Solve = Callable[[np.ndarray], np.ndarray]


def available_methods() -> tuple[str, ...]:
    """Factorization methods usable on this installation, the default first."""
    methods = ["superlu-nd", "superlu"]
    if _pardiso_module() is not None:
        methods.insert(1, "pardiso")
    return tuple(methods)


def resolve_method(method: str) -> FactorMethod:
    """The concrete method ``method`` stands for ("auto" -> "superlu-nd")."""
    if method not in METHODS:
        raise HitogataError(f"factorization method {method!r} is unknown; allowed: {', '.join(METHODS)}")
    if method == "auto":
        return "superlu-nd"
    if method not in available_methods():
        raise HitogataError(f"factorization method {method!r} is not installed; available: "
                            f"{', '.join(available_methods())} (pardiso needs `pip install pypardiso`)")
    return cast(FactorMethod, method)


def factorize(A: sp.spmatrix, method: FactorMethod = "auto", node_of_dof: np.ndarray | None = None,
              positive_definite: bool = True) -> Solve:
    """Factor a symmetric sparse matrix once; return ``solve(b)`` for b of shape (n,) or (n, m).

    ``node_of_dof`` (n,) groups dofs by mesh node so that the fill-reducing
    ordering works on the 3x smaller node graph; ``positive_definite`` lets
    PARDISO use Cholesky (otherwise LDL^T with pivoting).
    """
    A = sp.csr_matrix(A)
    method = resolve_method(method)
    if method == "pardiso":
        return _pardiso(A, positive_definite)
    if method == "superlu-nd":
        return _superlu_nd(A, node_of_dof, positive_definite)
    lu = sla.splu(A.tocsc())
    return lu.solve


def nested_dissection(A: sp.spmatrix, node_of_dof: np.ndarray | None = None) -> np.ndarray | None:
    """METIS nested-dissection permutation of A's graph (None without pymetis).

    With ``node_of_dof`` the node graph is ordered and each node's dofs are
    kept together, which is faster and gives supernodes aligned to nodes.
    """
    try:
        import pymetis
    except ImportError:
        return None
    n = A.shape[0]
    group = np.arange(n) if node_of_dof is None else np.unique(np.asarray(node_of_dof), return_inverse=True)[1]
    n_groups = int(group.max()) + 1 if n else 0
    coo = sp.coo_matrix(A)
    graph = sp.csr_matrix((np.ones(coo.nnz, dtype=np.int8), (group[coo.row], group[coo.col])),
                          shape=(n_groups, n_groups))
    graph.setdiag(0)
    graph.eliminate_zeros()
    graph.sort_indices()
    adjacency = pymetis.CSRAdjacency(graph.indptr.astype(np.int64), graph.indices.astype(np.int64))
    order, _ = pymetis.nested_dissection(adjacency)
    rank = np.empty(n_groups, dtype=np.int64)
    rank[np.asarray(order)] = np.arange(n_groups)
    return np.lexsort((np.arange(n), rank[group]))


def _superlu_nd(A: sp.csr_matrix, node_of_dof: np.ndarray | None, positive_definite: bool) -> Solve:
    """SuperLU on a symmetrically reordered matrix, pivoting on the diagonal only."""
    perm = nested_dissection(A, node_of_dof)
    options = {"SymmetricMode": True}
    pivot = 0.0 if positive_definite else 0.01
    if perm is None:
        lu = sla.splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=pivot, options=options)
        return lu.solve
    inverse = np.empty_like(perm)
    inverse[perm] = np.arange(len(perm))
    lu = sla.splu(A[perm][:, perm].tocsc(), permc_spec="NATURAL", diag_pivot_thresh=pivot, options=options)

    def solve(b: np.ndarray) -> np.ndarray:
        return lu.solve(np.ascontiguousarray(np.asarray(b)[perm]))[inverse]

    return solve


def _pardiso(A: sp.csr_matrix, positive_definite: bool) -> Solve:
    """MKL PARDISO on the upper triangle; forward/back substitution in parallel."""
    return _PardisoSolve(A, positive_definite)


class _PardisoSolve:
    """A PARDISO factorization that frees MKL's memory when it is dropped."""

    def __init__(self, A: sp.csr_matrix, positive_definite: bool) -> None:
        self.solver = _pardiso_module().PyPardisoSolver(mtype=2 if positive_definite else -2)
        self.solver.set_iparm(25, 2)  # parallel forward/backward substitution
        self.upper = sp.triu(A, format="csr")
        self.upper.sort_indices()
        self.solver.factorize(self.upper)

    def __call__(self, b: np.ndarray) -> np.ndarray:
        return self.solver.solve(self.upper, np.asarray(b, dtype=float))

    def __del__(self) -> None:
        self.solver.free_memory(everything=True)


def _pardiso_module():
    """The pypardiso module if it and MKL load, else None."""
    try:
        import pypardiso
    except (ImportError, OSError):
        return None
    return pypardiso


class SamePatternSolves:
    """``solve(A, b)`` for a sequence of matrices of one sparsity pattern (an iteration's Hessian, its values
    changing): scipy's ``spsolve`` (SuperLU, COLAMD's column order, partial pivoting), the column order found
    at the first matrix and kept for the next ones of the same pattern: finding it costs as much as the
    factorization itself on the skin slide's systems, and the answers are the same."""

    def __init__(self) -> None:
        self._pattern: tuple[np.ndarray, np.ndarray] | None = None
        self._order = np.zeros(0, dtype=np.int64)

    def __call__(self, A: sp.spmatrix, b: np.ndarray) -> np.ndarray:
        A = sp.csc_matrix(A)
        A.sum_duplicates()
        if self._pattern is None or not (np.array_equal(self._pattern[0], A.indptr)
                                         and np.array_equal(self._pattern[1], A.indices)):
            lu = sla.splu(A)
            self._pattern = (A.indptr.copy(), A.indices.copy())
            self._order = np.argsort(lu.perm_c)  # A[:, order] is the column order COLAMD chose
            return lu.solve(b)
        x = np.empty_like(b)
        x[self._order] = sla.splu(A[:, self._order], permc_spec="NATURAL").solve(b)
        return x


class InverseColumns:
    """Columns of A⁻¹ (A⁻¹ e_k for chosen k), solved once and kept: a constraint that touches a few
    unknowns (an element's volume: its four corners) then needs no solve of its own, only a combination
    of those columns. The columns not yet kept are solved in one batch; past `budget` bytes the kept
    ones are dropped and solved again as needed."""

    def __init__(self, solve: Solve, size: int, budget: int = 256 * 2**20) -> None:
        self._solve = solve
        self._size = size
        self._capacity = max(1, budget // (8 * max(size, 1)))
        self._slot = np.full(size, -1, dtype=np.int64)
        self._store = np.empty((size, 0))
        self._kept = 0

    def __call__(self, indices: np.ndarray) -> np.ndarray:
        """(size, len(indices)): A⁻¹ e_k for each k in `indices` (unknowns 0 … size − 1)."""
        indices = np.asarray(indices, dtype=np.int64)
        wanted = np.unique(indices)
        if len(wanted) > self._capacity:  # more than the budget keeps: solved, not kept
            return self._solve(self._units(wanted))[:, np.searchsorted(wanted, indices)]
        missing = wanted[self._slot[wanted] < 0]
        if len(missing):
            if self._kept + len(missing) > self._capacity:
                self._slot[:] = -1
                self._kept = 0
                missing = wanted
            if self._kept + len(missing) > self._store.shape[1]:
                grown = np.empty((self._size, min(self._capacity, max(2 * self._store.shape[1],
                                                                      self._kept + len(missing)))))
                grown[:, :self._kept] = self._store[:, :self._kept]
                self._store = grown
            self._store[:, self._kept:self._kept + len(missing)] = self._solve(self._units(missing))
            self._slot[missing] = self._kept + np.arange(len(missing))
            self._kept += len(missing)
        return self._store[:, self._slot[indices]]

    def _units(self, indices: np.ndarray) -> np.ndarray:
        unit = np.zeros((self._size, len(indices)))
        unit[indices, np.arange(len(indices))] = 1.0
        return unit
