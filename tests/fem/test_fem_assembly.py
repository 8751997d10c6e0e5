"""Assembly of K and M: against scikit-fem on the identical mesh, invariants, pattern reuse, materials."""

import numpy as np
import pytest
import scipy.linalg as la

from hitogata.errors import HitogataError
from hitogata.fem.assembly import lumped_masses, mass_matrix, sparsity, stiffness_matrix
from hitogata.fem.verify.box_mesh import box_mesh
from hitogata.fem.elements import MATERIAL_SAMPLES, lift_node_set, p2_mesh, sample_points
from hitogata.fem.materials import Material, region_materials
from hitogata.fem.modes import solve_modes

skfem = pytest.importorskip("skfem")
from skfem.helpers import dot  # noqa: E402
from skfem.models.elasticity import lame_parameters, linear_elasticity  # noqa: E402

E, NU, RHO = 1e6, 0.3, 1000.0


def cantilever(div, order):
    points, tets = box_mesh((1.0, 0.1, 0.1), div)
    fixed = np.flatnonzero(points[:, 0] < 1e-12)
    if order == 2:
        points, tets2 = p2_mesh(points, tets)
        return points, tets2, lift_node_set(tets2, fixed), tets
    return points, tets, fixed, tets


def skfem_eigenvalues(p1_points, p1_tets, order, k):
    """Lowest k eigenvalues from scikit-fem's own assembly, dof numbering and constraint handling."""
    mesh = skfem.MeshTet(p1_points.T.copy(), p1_tets.T.copy())
    element = skfem.ElementVector(skfem.ElementTetP1() if order == 1 else skfem.ElementTetP2())
    basis = skfem.Basis(mesh, element, intorder=2 * order)
    K = linear_elasticity(*lame_parameters(E, NU)).assemble(basis)

    @skfem.BilinearForm
    def mass(u, v, _):
        return RHO * dot(u, v)

    M = mass.assemble(basis)
    clamped = basis.get_dofs(lambda x: x[0] < 1e-12)
    Kc, Mc, *_ = skfem.condense(K, M, D=clamped, expand=False)
    return la.eigh(Kc.toarray(), Mc.toarray(), subset_by_index=[0, k - 1], eigvals_only=True)


@pytest.mark.parametrize("order,div", [(1, (6, 2, 2)), (2, (4, 1, 1))])
def test_first_ten_eigenvalues_equal_scikit_fem(order, div):
    points, tets, fixed, p1_tets = cantilever(div, order)
    K = stiffness_matrix(points, tets, E, NU)
    M = mass_matrix(points, tets, RHO)
    ours = solve_modes(K, M, 10, fixed, solver="dense").eigenvalues
    theirs = skfem_eigenvalues(points[: p1_tets.max() + 1], p1_tets, order, 10)
    rel = np.abs(ours / theirs - 1.0).max()
    print(f"P{order}: max relative difference of the first 10 eigenvalues vs scikit-fem {rel:.1e}")
    assert rel < 1e-6


@pytest.mark.parametrize("order", [1, 2])
def test_rigid_motions_are_free_and_mass_is_exact(order):
    points, tets, _, _ = cantilever((3, 2, 2), order)
    K = stiffness_matrix(points, tets, E, NU)
    assert abs(K - K.T).max() == 0.0
    x, y, z = points.T
    one, zero = np.ones(len(points)), np.zeros(len(points))
    rigid = [np.stack(c, axis=1).ravel() for c in
             [(one, zero, zero), (zero, one, zero), (zero, zero, one), (-y, x, zero), (zero, -z, y), (z, zero, -x)]]
    for r in rigid:
        assert np.abs(K @ r).max() < 1e-9 * abs(K).max() * np.abs(r).max()
    M = mass_matrix(points, tets, RHO)
    total = RHO * 0.01
    for i in range(3):
        assert rigid[i] @ M @ rigid[i] == pytest.approx(total, rel=1e-13)
    lumped = lumped_masses(points, tets, RHO)
    assert np.all(lumped > 0)  # HRZ keeps P2 corner masses positive
    assert lumped.sum() == pytest.approx(3 * total, rel=1e-13)
    assert np.diag(mass_matrix(points, tets, RHO, lumped=True).toarray()) == pytest.approx(lumped)


def test_pattern_reuse_and_region_materials_match_fresh_assembly():
    points, tets, _, _ = cantilever((4, 2, 2), 2)
    pattern = sparsity(tets, len(points))
    regions = (points[tets[:, :4]].mean(axis=1)[:, 0] > 0.5).astype(int)
    table = {0: Material(1e6, 0.3, 1000.0, "muscle"), 1: Material(2e4, 0.45, 950.0, "fat")}
    E_el, nu_el, rho_el = region_materials(regions, table)
    K_reused = stiffness_matrix(points, tets, E_el, nu_el, pattern)
    K_fresh = stiffness_matrix(points, tets, E_el, nu_el)
    assert abs(K_reused - K_fresh).max() == 0.0
    # the region split equals the sum of the two regions assembled alone
    K0 = stiffness_matrix(points, tets[regions == 0], 1e6, 0.3).toarray()
    K1 = stiffness_matrix(points, tets[regions == 1], 2e4, 0.45).toarray()
    assert np.abs(K_fresh.toarray() - K0 - K1).max() <= 1e-12 * abs(K_fresh).max()
    M = mass_matrix(points, tets, rho_el, pattern=pattern)
    assert np.array_equal(M.indptr, K_reused.indptr) and np.array_equal(M.indices, K_reused.indices)
    assert M.sum() / 3 == pytest.approx(0.005 * 1000.0 + 0.005 * 950.0, rel=1e-13)


def test_materials_sampled_inside_elements():
    """Per-sample-point materials: uniform samples reproduce per-element assembly; a density step
    crossing the elements is integrated where it lies, not where the centroids put it."""
    points, tets, _, p1_tets = cantilever((4, 1, 1), 2)  # elements 0.25 m long
    n_samples = len(MATERIAL_SAMPLES[1])
    E_el = np.linspace(1e5, 1e6, len(tets))
    same = np.repeat(E_el[:, None], n_samples, axis=1)
    for dilatation in ("full", "mean"):
        K_el = stiffness_matrix(points, tets, E_el, NU, dilatation=dilatation)
        K_q = stiffness_matrix(points, tets, same, NU, dilatation=dilatation)
        assert abs(K_q - K_el).max() <= 1e-12 * abs(K_el).max()
    M_el = mass_matrix(points, tets, RHO)
    M_q = mass_matrix(points, tets, np.full((len(tets), n_samples), RHO))
    assert abs(M_q - M_el).max() <= 1e-12 * abs(M_el).max()

    step = 0.3  # dense below x = 0.3 m, inside the second element (0.25-0.5 m)
    exact = 0.01 * (2000.0 * step + 1000.0 * (1.0 - step))
    centroid = np.where(points[p1_tets].mean(axis=1)[:, 0] < step, 2000.0, 1000.0)
    sampled = np.where(sample_points(points, tets)[..., 0] < step, 2000.0, 1000.0)
    error = {name: abs(mass_matrix(points, tets, rho).sum() / 3 / exact - 1)
             for name, rho in (("centroid", centroid), ("sampled", sampled))}
    print(f"\nmass of a bar with a density step inside an element: error {error}")
    assert error["centroid"] > 0.035 and error["sampled"] < 0.2 * error["centroid"]
    with pytest.raises(HitogataError, match=r"E has shape \(24, 5\)"):
        stiffness_matrix(points, tets, np.ones((len(tets), 5)), NU)


def test_mean_dilatation_keeps_rigid_motions_and_equals_full_for_linear_tets():
    points, tets, _, p1_tets = cantilever((3, 2, 2), 2)
    K = stiffness_matrix(points, tets, E, 0.49, dilatation="mean")
    assert abs(K - K.T).max() == 0.0
    x, y, z = points.T
    one, zero = np.ones(len(points)), np.zeros(len(points))
    for r in [np.stack(c, axis=1).ravel() for c in [(one, zero, zero), (-y, x, zero), (z, zero, -x)]]:
        assert np.abs(K @ r).max() < 1e-9 * abs(K).max() * np.abs(r).max()
    # A uniform strain has a constant dilatation: both forms give the same nodal forces.
    strain = np.stack([0.01 * x, -0.003 * y, 0.002 * z + 0.004 * x], axis=1).ravel()
    K_full = stiffness_matrix(points, tets, E, 0.49)
    assert np.allclose(K @ strain, K_full @ strain, rtol=0, atol=1e-9 * np.abs(K_full @ strain).max())
    # ... and they differ otherwise (that is the point).
    assert abs(K - K_full).max() > 0.01 * abs(K_full).max()
    p1_points = points[: p1_tets.max() + 1]
    K1 = stiffness_matrix(p1_points, p1_tets, E, 0.49, dilatation="mean")
    K1_full = stiffness_matrix(p1_points, p1_tets, E, 0.49)
    assert abs(K1 - K1_full).max() <= 1e-12 * abs(K1_full).max()
    with pytest.raises(HitogataError, match="dilatation 'half': allowed full, mean"):
        stiffness_matrix(points, tets, E, NU, dilatation="half")
