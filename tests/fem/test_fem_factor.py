"""Kept columns of a factored matrix's inverse (`fem.factor.InverseColumns`), and the quasi-statics' floor
repairs built on them: the same multipliers and moves as back-substituting every held element's gradient;
solves of matrices of one pattern with a kept column order (`fem.factor.SamePatternSolves`): scipy's
`spsolve`'s answers."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from hitogata.dynamics.quasistatic import FLOOR, STEP_CAP, QuasiStatic
from hitogata.dynamics.volumes import corner_volumes, volumes_and_gradients
from hitogata.fem.factor import InverseColumns, SamePatternSolves, factorize
from hitogata.fem.verify.box_mesh import box_mesh


def grid_laplacian(n: int) -> sp.csr_matrix:
    """A 2-D grid's Laplacian plus the identity: sparse, symmetric positive definite, n² unknowns."""
    line = sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1])
    return sp.csr_matrix(sp.kron(line, sp.eye(n)) + sp.kron(sp.eye(n), line) + sp.eye(n * n))


class Counted:
    """A solve that counts the right-hand sides it is given."""

    def __init__(self, solve) -> None:
        self.solve, self.columns = solve, 0

    def __call__(self, b: np.ndarray) -> np.ndarray:
        self.columns += b.shape[1]
        return self.solve(b)


def test_kept_columns_are_the_inverse_and_are_solved_once():
    A = grid_laplacian(12)
    inverse = np.linalg.inv(A.toarray())
    solve = Counted(factorize(A))
    columns = InverseColumns(solve, A.shape[0])
    idx = np.array([[3, 7, 7, 100], [3, 0, 143, 50]])
    assert np.allclose(columns(idx), inverse[:, idx], rtol=0, atol=1e-12)
    assert solve.columns == 6  # each distinct index once
    assert np.allclose(columns(np.array([0, 50, 51])), inverse[:, [0, 50, 51]], rtol=0, atol=1e-12)
    assert solve.columns == 7  # only 51 was new


def test_past_the_budget_columns_are_solved_again_and_still_right():
    A = grid_laplacian(10)
    inverse = np.linalg.inv(A.toarray())
    solve = Counted(factorize(A))
    columns = InverseColumns(solve, A.shape[0], budget=8 * A.shape[0] * 4)  # room for 4 columns
    assert np.allclose(columns(np.array([1, 2, 3])), inverse[:, [1, 2, 3]], atol=1e-12)
    assert np.allclose(columns(np.array([4, 5])), inverse[:, [4, 5]], atol=1e-12)  # the kept ones dropped
    assert solve.columns == 5
    assert np.allclose(columns(np.arange(10, 20)), inverse[:, 10:20], atol=1e-12)  # more than it keeps
    assert solve.columns == 15


def test_floor_repair_step_equals_back_substituting_every_gradient():
    """A block of two tissue regions held at its base, its top layer pressed to 1 % of its height: the repair
    projection holds the elements and moves the nodes that every held gradient back-substituted gives."""
    points, elements = box_mesh((0.1, 0.1, 0.1), (4, 4, 4))
    fixed = np.flatnonzero(points[:, 2] < 1e-9)
    region = np.where(points[elements].mean(axis=1)[:, 0] < 0.05, 1, 2)
    statics = QuasiStatic(points, elements, 20e3, 0.45, fixed, region, (1, 2))
    crushed = points.copy()
    top = points[:, 2] > 0.08
    crushed[top, 2] = 0.075 + (points[top, 2] - 0.075) * 0.01
    active = np.flatnonzero(corner_volumes(crushed, elements) < FLOOR * statics.rest_element_volumes)
    assert len(active) > 10
    moved, held = statics._project(crushed, np.zeros(0, dtype=int))

    free = statics.free
    column = np.full(len(points), -1)
    column[free] = np.arange(len(free))

    def response(gradients: np.ndarray) -> np.ndarray:  # L⁻¹g, one right-hand side at a time
        return np.stack([np.stack([statics._solve(np.ascontiguousarray(g[:, k])) for k in range(3)], axis=-1)
                         for g in gradients])

    volumes, region_gradients = statics._volume_gradients(crushed)
    v, g = volumes_and_gradients(crushed, elements[active, :4])
    element_gradients = np.zeros((len(active), len(free), 3))
    for a in range(4):
        c = column[elements[active, a]]
        keep = np.flatnonzero(c >= 0)
        element_gradients[keep, c[keep]] += g[:, a].T[keep]
    G = np.concatenate([region_gradients, element_gradients])
    R = response(G)
    targets = np.concatenate([statics.rest_volumes - volumes, FLOOR * statics.rest_element_volumes[active] - v])
    p = np.linalg.lstsq(np.einsum("rfk,sfk->rs", G, R), targets, rcond=1e-12)[0]
    assert held is not None and np.array_equal(held, active[p[2:] >= 0.0]) and len(held)
    move = np.einsum("r,rfk->fk", p, R)
    expected = crushed.copy()
    expected[free] += move * min(1.0, STEP_CAP / float(np.abs(move).max()))
    volumes, gradients = statics._volume_gradients(expected)
    R = response(gradients)
    expected[free] += np.einsum("r,rfk->fk", np.linalg.solve(np.einsum("rfk,sfk->rs", gradients, R),
                                                             statics.rest_volumes - volumes), R)
    assert np.abs(moved - expected).max() < 1e-12  # m


def test_solves_of_one_pattern_are_spsolves_bit_for_bit():
    """The slide's systems change their values, never their pattern: the column order COLAMD finds at the
    first is kept, and every answer is scipy's `spsolve`'s to the last bit; a new pattern is ordered anew."""
    rng = np.random.default_rng(3)
    base = sp.coo_matrix(grid_laplacian(30))
    solve = SamePatternSolves()
    for k in range(4):
        values = base.data * rng.uniform(0.5, 2.0, base.nnz)  # not symmetric: partial pivoting has work to do
        A = sp.csc_matrix((values, (base.row, base.col)), shape=base.shape)
        b = rng.normal(size=A.shape[0])
        assert np.array_equal(solve(A, b), sla.spsolve(A, b)), k
    wider = sp.csc_matrix(grid_laplacian(30) + sp.eye(900, k=30) * 0.3)  # another pattern
    b = rng.normal(size=900)
    assert np.array_equal(solve(wider, b), sla.spsolve(wider, b))
    assert np.allclose(wider @ solve(wider, b), b, rtol=0, atol=1e-12)
