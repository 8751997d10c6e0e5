"""The elastic body's finite-element core: tets, K and M, modes, modal dynamics, loads.

Plain functions over numpy arrays (points (N, 3) in metres, tets (T, 4) for
linear or (T, 10) for quadratic elements, node-major dofs 3 * node + axis)
and scipy.sparse CSR matrices; independent of the body geometry.

Typical use::

    points2, tets2 = p2_mesh(points, tets)                # quadratic elements (the default choice)
    fixed2 = lift_node_set(tets2, bone_nodes)             # bone nodes follow the skeleton
    E, nu, rho = region_materials(regions, materials)     # one material per tissue region
    pattern = sparsity(tets2, len(points2))
    K = stiffness_matrix(points2, tets2, E, nu, pattern)
    M = mass_matrix(points2, tets2, rho, pattern=pattern)
    modes = solve_modes(K, M, 40, fixed2)                 # modes.frequencies in Hz
    f = eigenstrain_load(points2, tets2, E, nu, muscle_eigenstrain(fibres, 0.1), elements=muscle)
    q, qd = integrate_modes(modes.eigenvalues, alpha, beta, dt, modal_loads(modes.vectors, forces))
    u = superpose(modes.vectors, q)

Why P2: linear tets are too stiff in bending (+9 % on a cantilever's first
frequency at 3,000 dof, where P2 is within 0.7 %) and lock as nu -> 0.5
(+99 % at nu = 0.49 vs +2 % for P2); see ``verify.poisson_sweep``.

Reference solutions and test meshes that only the tests and benchmarks use
(Newmark, exact responses, static solves, box meshes) live in ``hitogata.fem.verify``.
"""

from hitogata.fem.assembly import Pattern, lumped_masses, mass_matrix, sparsity, stiffness_matrix
from hitogata.fem.damping import (
    damping_matrix,
    damping_ratios,
    modal_damping,
    rayleigh_coefficients,
)
from hitogata.fem.elements import boundary_triangles, check_mesh, lift_node_set, p2_mesh, tet_geometry
from hitogata.fem.factor import available_methods, factorize
from hitogata.fem.loads import (
    eigenstrain_load,
    fibre_eigenstrain,
    gravity_load,
    muscle_eigenstrain,
    nodal_load,
    traction_load,
)
from hitogata.fem.materials import Material, region_materials
from hitogata.fem.modal_dynamics import (
    ModalStep,
    advance,
    integrate_modes,
    modal_energy,
    modal_loads,
    modal_step,
    superpose,
)
from hitogata.fem.modes import Modes, frequencies_hz, no_modes, solve_modes

__all__ = [
    "Material", "ModalStep", "Modes", "Pattern",
    "advance", "available_methods", "boundary_triangles", "check_mesh", "damping_matrix",
    "damping_ratios", "eigenstrain_load", "factorize", "fibre_eigenstrain",
    "frequencies_hz", "gravity_load", "integrate_modes", "lift_node_set", "lumped_masses", "mass_matrix",
    "modal_damping", "modal_energy", "modal_loads", "modal_step", "muscle_eigenstrain",
    "no_modes", "nodal_load", "p2_mesh", "rayleigh_coefficients", "region_materials", "solve_modes",
    "sparsity", "stiffness_matrix", "superpose", "tet_geometry", "traction_load",
]
