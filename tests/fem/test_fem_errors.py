"""Bad input to the FEM core raises HitogataError with a one-line message naming the value and the rule."""

import numpy as np
import pytest

from hitogata.errors import HitogataError
from hitogata.fem.assembly import mass_matrix, stiffness_matrix
from hitogata.fem.verify.box_mesh import box_mesh
from hitogata.fem.elements import p2_mesh
from hitogata.fem.factor import factorize
from hitogata.fem.loads import fibre_eigenstrain, traction_load
from hitogata.fem.materials import Material, region_materials
from hitogata.fem.modal_dynamics import integrate_modes
from hitogata.fem.modes import solve_modes
from hitogata.fem.verify.static import solve_static

POINTS, TETS = box_mesh((1.0, 0.1, 0.1), (2, 1, 1))


def raises(match, fn, *args, **kwargs):
    with pytest.raises(HitogataError, match=match) as info:
        fn(*args, **kwargs)
    assert "\n" not in str(info.value)
    return str(info.value)


@pytest.mark.parametrize("E,nu,match", [
    (0.0, 0.3, r"E = 0\.0 .*allowed: > 0"),
    (-5.0, 0.3, r"E = -5\.0"),
    (np.nan, 0.3, r"E = nan"),
    (1e6, 0.5, r"nu = 0\.5 .*allowed: 0 <= nu < 0\.5"),
    (1e6, -0.1, r"nu = -0\.1"),
    (1e6, 0.7, r"nu = 0\.7"),
])
def test_bad_elastic_constants(E, nu, match):
    raises(match, stiffness_matrix, POINTS, TETS, E, nu)


def test_bad_density_and_materials():
    raises(r"rho = 0\.0 .*allowed: > 0", mass_matrix, POINTS, TETS, 0.0)
    raises(r"rho = -1\.0 \(element 0\)", mass_matrix, POINTS, TETS, np.full(len(TETS), -1.0))
    raises(r"fat: nu = 0\.5", Material, 1e4, 0.5, 900.0, "fat")
    raises(r"region 2 has no material", region_materials, np.array([0, 2]), {0: Material(1e4, 0.3, 900.0)})
    raises(r"E has shape \(3,\)", stiffness_matrix, POINTS, TETS, np.ones(3), 0.3)


def test_bad_meshes():
    flipped = TETS.copy()
    flipped[3, [1, 2]] = flipped[3, [2, 1]]
    message = raises(r"tet 3 is inverted", stiffness_matrix, POINTS, flipped, 1e6, 0.3)
    assert "signed volume" in message
    flat = POINTS.copy()
    flat[:, 2] = 0.0
    raises(r"inverted or flat", stiffness_matrix, flat, TETS, 1e6, 0.3)
    raises(r"node index 999 is out of range; allowed: 0\.\.11", stiffness_matrix, POINTS,
           np.vstack([TETS, [0, 1, 2, 999]]), 1e6, 0.3)
    raises(r"shape \(12, 5\)", stiffness_matrix, POINTS, np.zeros((12, 5), int), 1e6, 0.3)
    raises(r"needs a P1 mesh", p2_mesh, *p2_mesh(POINTS, TETS))
    raises(r"box divisions", box_mesh, (1, 1, 1), (0, 1, 1))
    raises(r"box lengths", box_mesh, (1, -1, 1), (1, 1, 1))


def test_bad_constraints_and_solver_options():
    K = stiffness_matrix(POINTS, TETS, 1e6, 0.3)
    M = mass_matrix(POINTS, TETS, 1000.0)
    raises(r"fixed node index 12 is out of range; allowed: 0\.\.11", solve_modes, K, M, 3, [0, 12])
    raises(r"fixed node index -1", solve_modes, K, M, 3, [-1])
    raises(r"fixed dof index 36 is out of range; allowed: 0\.\.35", solve_static, K, np.zeros(36), fixed_dofs=[36])
    raises(r"n_modes = 0", solve_modes, K, M, 0, [0, 1])
    raises(r"eigen solver 'magic' is unknown", solve_modes, K, M, 3, [0, 1], solver="magic")
    raises(r"factorization method 'lu'", factorize, K, "lu")
    raises(r"no dof is fixed", solve_static, K, np.zeros(36))
    raises(r"force vector has shape \(3,\)", solve_static, K, np.zeros(3), fixed_nodes=[0, 1, 2])
    raises(r"dt = -0\.1", integrate_modes, np.ones(2), 0.0, 0.0, -0.1, np.zeros((3, 2)))
    raises(r"Rayleigh alpha = -1", integrate_modes, np.ones(2), -1.0, 0.0, 0.1, np.zeros((3, 2)))
    raises(r"modal loads have shape \(3, 5\)", integrate_modes, np.ones(2), 0.0, 0.0, 0.1, np.zeros((3, 5)))
    raises(r"load hold 'cubic'", integrate_modes, np.ones(2), 0.0, 0.0, 0.1, np.zeros((3, 2)), hold="cubic")
    raises(r"fibre directions", fibre_eigenstrain, np.zeros((2, 3)), 0.1)
    raises(r"faces have shape", traction_load, POINTS, np.zeros((2, 4), int), (1, 0, 0))
