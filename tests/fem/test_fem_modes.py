"""Modal analysis: a clamped cantilever against Timoshenko beam theory, convergence, solver agreement."""

import numpy as np
import pytest

from hitogata.fem.verify.box_mesh import cantilever_system
from hitogata.fem.factor import available_methods
from hitogata.fem.modes import frequencies_hz, solve_modes

# cantilever_system: 1 x 0.1 x 0.1 m, E = 1 MPa, nu = 0.3, rho = 1000 kg/m^3, clamped at x = 0.
E, RHO = 1e6, 1000.0
TIMOSHENKO_HZ = 0.50687  # first bending frequency (Euler-Bernoulli: 0.51083 Hz)


def test_euler_bernoulli_reference_value():
    # sanity of the constants: beta1 L = 1.8751, f = (beta1 L)^2 / (2 pi) sqrt(E I / (rho A L^4))
    f_eb = 1.8751040687**2 / (2 * np.pi) * np.sqrt(E * 0.1**4 / 12 / (RHO * 0.01))
    assert f_eb == pytest.approx(0.51083, abs=5e-6)


def test_default_element_within_one_percent_of_timoshenko():
    """P2 tets, 20 x 2 x 2 cells (480 tets, 3075 dof): first bending frequency within 1 %."""
    K, M, fixed = cantilever_system((20, 2, 2), 2)
    f = solve_modes(K, M, 4, fixed).frequencies
    err = f[0] / TIMOSHENKO_HZ - 1.0
    print(f"P2 480 tets: f1 = {f[0]:.5f} Hz, error vs Timoshenko {err:+.3%}")
    assert abs(err) < 0.01
    assert f[1] / f[0] - 1.0 < 0.002  # the two bending directions of a square section agree


def test_mean_dilatation_converges_to_the_same_frequency():
    """P2 on the mean dilatation (the elastic body's default) is softer on coarse meshes and
    converges from below, to the limit of the full form; within 1 % at 30 x 3 x 3 cells (12,150 dof)."""
    errors = []
    for div in [(10, 1, 1), (20, 2, 2), (30, 3, 3)]:
        K, M, fixed = cantilever_system(div, 2, dilatation="mean")
        errors.append(solve_modes(K, M, 1, fixed).frequencies[0] / TIMOSHENKO_HZ - 1.0)
    print("P2 mean-dilatation errors vs Timoshenko over refinement: " + ", ".join(f"{e:+.2%}" for e in errors))
    assert errors[0] < errors[1] < errors[2] < 0.01 and abs(errors[2]) < 0.01  # -8.0 %, -1.2 %, -0.2 %


@pytest.mark.parametrize("order,divisions", [
    (1, [(10, 1, 1), (20, 2, 2), (40, 4, 4)]),
    (2, [(5, 1, 1), (10, 1, 1), (20, 2, 2)]),
])
def test_error_decreases_with_refinement(order, divisions):
    errors = []
    for div in divisions:
        K, M, fixed = cantilever_system(div, order)
        errors.append(solve_modes(K, M, 1, fixed).frequencies[0] / TIMOSHENKO_HZ - 1.0)
    print(f"P{order} errors vs Timoshenko over refinement: " + ", ".join(f"{e:+.2%}" for e in errors))
    assert all(e > 0 for e in errors)  # conforming displacement FE is stiff: converges from above
    assert errors[0] > errors[1] > errors[2]
    if order == 1:
        assert errors[-1] > 0.05  # linear tets stay far off at 3,840 tets (bending stiffness)


@pytest.mark.parametrize("solver", ["dense", "scipy"] + [m for m in available_methods() if m != "superlu"])
def test_solvers_agree_and_modes_are_mass_normalised(solver):
    K, M, fixed = cantilever_system((8, 1, 1), 2)  # 432 free dofs
    reference = solve_modes(K, M, 12, fixed, solver="dense")
    modes = solve_modes(K, M, 12, fixed, solver=solver)
    assert np.abs(modes.eigenvalues / reference.eigenvalues - 1).max() < 1e-9
    phi = modes.vectors
    assert np.allclose(phi.T @ M @ phi, np.eye(12), atol=1e-9)
    assert np.allclose(phi.T @ K @ phi, np.diag(modes.eigenvalues), rtol=1e-9, atol=1e-9 * modes.eigenvalues.max())
    fixed_dofs = (3 * fixed[:, None] + np.arange(3)).ravel()
    assert np.all(phi[fixed_dofs] == 0.0)
    assert np.allclose(modes.frequencies, np.sqrt(modes.eigenvalues) / (2 * np.pi))


def test_free_body_has_six_zero_modes():
    K, M, _ = cantilever_system((6, 1, 1), 2)
    modes = solve_modes(K, M, 8, fixed_nodes=None)
    assert np.all(modes.frequencies[:6] < 1e-5 * modes.frequencies[6])
    assert frequencies_hz(np.array([-1e-12]))[0] == 0.0


def test_superlu_nd_falls_back_without_pymetis(monkeypatch):
    import sys

    K, M, fixed = cantilever_system((6, 1, 1), 2)
    with_metis = solve_modes(K, M, 5, fixed, solver="superlu-nd").eigenvalues
    monkeypatch.setitem(sys.modules, "pymetis", None)  # import now fails
    without = solve_modes(K, M, 5, fixed, solver="superlu-nd").eigenvalues
    assert np.allclose(with_metis, without, rtol=1e-10)
