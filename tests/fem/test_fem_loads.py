"""Loads and statics: eigenstrain on a free bar, gravity on a cantilever, surface traction, prescribed dofs."""

import numpy as np
import pytest

from hitogata.errors import HitogataError
from hitogata.fem.assembly import stiffness_matrix
from hitogata.fem.verify.box_mesh import box_mesh
from hitogata.fem.elements import MATERIAL_SAMPLES, boundary_triangles, lift_node_set, p2_mesh, sample_points
from hitogata.fem.loads import (
    eigenstrain_load,
    fibre_eigenstrain,
    gravity_load,
    muscle_eigenstrain,
    nodal_load,
    traction_load,
)
from hitogata.fem.verify.static import StaticSolver, solve_static

L, W = 1.0, 0.1
E, NU, RHO = 1e6, 0.3, 1000.0


def bar(order, div=(6, 2, 2)):
    points, tets = box_mesh((L, W, W), div)
    if order == 2:
        points, tets = p2_mesh(points, tets)
    return points, tets


def node_at(points, x):
    return int(np.argmin(np.linalg.norm(points - np.asarray(x), axis=1)))


def minimal_supports(points):
    """Six dofs that stop rigid motion without restraining any expansion: statically determinate."""
    a, b, c = node_at(points, (0, 0, 0)), node_at(points, (L, 0, 0)), node_at(points, (0, W, 0))
    return [3 * a, 3 * a + 1, 3 * a + 2, 3 * b + 1, 3 * b + 2, 3 * c + 2]


def extent(points, u):
    moved = points + u.reshape(-1, 3)
    return moved.max(axis=0) - moved.min(axis=0)


@pytest.mark.parametrize("order", [1, 2])
def test_free_bar_with_uniform_eigenstrain_changes_length_by_eps_L(order):
    points, tets = bar(order)
    K = stiffness_matrix(points, tets, E, NU)
    eps = 2e-3
    strain = fibre_eigenstrain(np.tile([1.0, 0.0, 0.0], (len(tets), 1)), eps)
    u = solve_static(K, eigenstrain_load(points, tets, E, NU, strain), fixed_dofs=minimal_supports(points))
    size = extent(points, u)
    assert (size[0] - L) / (eps * L) == pytest.approx(1.0, rel=1e-6)
    assert abs(size[1] - W) < 1e-9 * W and abs(size[2] - W) < 1e-9 * W  # free: no Poisson contraction
    # the strain field equals the eigenstrain everywhere: displacement is exactly linear in x
    assert np.allclose(u.reshape(-1, 3)[:, 0], eps * points[:, 0], atol=1e-12)


def test_muscle_contraction_shortens_and_isochoric_keeps_volume():
    points, tets = bar(2)
    K = stiffness_matrix(points, tets, E, 0.45)
    fibres = np.tile([1.0, 0.0, 0.0], (len(tets), 1))
    solver = StaticSolver(K, fixed_dofs=minimal_supports(points))
    contraction = 0.05  # positive = shortening
    u = solver.solve(eigenstrain_load(points, tets, E, 0.45, muscle_eigenstrain(fibres, contraction)))
    size = extent(points, u)
    assert size[0] == pytest.approx(L * (1 - contraction), rel=1e-9)
    assert size[1] == pytest.approx(W * (1 + contraction / 2), rel=1e-9)  # isochoric: section thickens
    assert np.prod(size) == pytest.approx(L * W * W * (1 - contraction) * (1 + contraction / 2) ** 2, rel=1e-12)
    stretched = solver.solve(eigenstrain_load(points, tets, E, 0.45, muscle_eigenstrain(fibres, -contraction)))
    assert extent(points, stretched)[0] == pytest.approx(L * (1 + contraction), rel=1e-9)
    # eigenstrain in some elements only: the rest is loaded by them, the total force is zero
    some = np.arange(len(tets)) % 3 == 0
    f = eigenstrain_load(points, tets, E, 0.45, muscle_eigenstrain(fibres[some], contraction), elements=some)
    assert np.abs(f.reshape(-1, 3).sum(axis=0)).max() < 1e-9 * np.abs(f).max()


@pytest.mark.parametrize("order", [1, 2])
def test_gravity_total_and_cantilever_sag(order):
    points, tets = bar(order, (20, 2, 2))
    f = gravity_load(points, tets, RHO)
    assert f.reshape(-1, 3).sum(axis=0) == pytest.approx([0.0, -9.81 * RHO * L * W * W, 0.0], abs=1e-9)
    if order == 1:
        return
    fixed = np.flatnonzero(points[:, 0] < 1e-12)
    K = stiffness_matrix(points, tets, E, NU)
    u = solve_static(K, f, fixed_nodes=fixed)
    tip = -u.reshape(-1, 3)[points[:, 0] > L - 1e-9, 1].mean()
    q, inertia, shear = 9.81 * RHO * W * W, W**4 / 12, 5 / 6 * E / (2 * (1 + NU)) * W * W
    timoshenko = q * L**4 / (8 * E * inertia) + q * L**2 / (2 * shear)
    print(f"P2 tip sag under gravity {tip:.4f} m, Timoshenko beam {timoshenko:.4f} m ({tip / timoshenko - 1:+.2%})")
    assert -0.02 < tip / timoshenko - 1 < 0.0  # conforming FE is slightly stiff; 3D clamping stiffens too


@pytest.mark.parametrize("order", [1, 2])
def test_end_traction_gives_uniform_tension(order):
    points, tets = bar(order)
    faces = boundary_triangles(tets)
    end = faces[np.all(points[faces[:, :3], 0] > L - 1e-9, axis=1)]
    sigma = 1e4
    f = traction_load(points, end, (sigma, 0.0, 0.0))
    assert f.reshape(-1, 3).sum(axis=0) == pytest.approx([sigma * W * W, 0, 0], rel=1e-12)
    roller = np.flatnonzero(points[:, 0] < 1e-12)
    supports = [3 * n for n in roller] + minimal_supports(points)[1:3] + minimal_supports(points)[5:]
    u = solve_static(stiffness_matrix(points, tets, E, NU), f, fixed_dofs=supports)
    size = extent(points, u)
    assert (size[0] - L) / (sigma * L / E) == pytest.approx(1.0, rel=1e-9)
    assert (size[1] - W) / (-NU * sigma * W / E) == pytest.approx(1.0, rel=1e-9)


def test_prescribed_displacement_and_point_loads():
    points, tets = bar(2)
    p1_points, p1_tets = bar(1)
    K = stiffness_matrix(points, tets, E, NU)
    left = lift_node_set(tets, np.flatnonzero(p1_points[:, 0] < 1e-12))
    right = np.flatnonzero(points[:, 0] > L - 1e-9)
    prescribed = np.zeros(K.shape[0])
    prescribed[3 * right] = 0.01  # pull the right end 1 cm; left end held
    solver = StaticSolver(K, fixed_nodes=np.concatenate([left, right]))
    u = solver.solve(np.zeros(K.shape[0]), prescribed)
    assert np.allclose(u[3 * right], 0.01) and np.allclose(u[3 * left], 0.0)
    mid = np.flatnonzero(np.abs(points[:, 0] - 0.5) < 1e-9)
    assert u[3 * mid].mean() == pytest.approx(0.005, rel=0.02)
    f = nodal_load(len(points), right, (0.0, 0.0, 2.0))
    assert f.reshape(-1, 3).sum(axis=0) == pytest.approx([0, 0, 2.0 * len(right)])


def test_eigenstrain_at_sample_points_where_the_tissue_lies():
    """Per-sample eigenstrain: uniform samples give the per-element forces; a strain ending inside
    an element (x < 0.3 m, the elements 0.25 m long) lengthens a free bar by about eps * 0.3 m
    (0.312), where a per-element strain (by centroid) gives eps * 0.25 m."""
    points, tets = bar(2, (4, 1, 1))
    p1 = points[tets[:, :4]]
    n_samples = len(MATERIAL_SAMPLES[1])
    eps = 2e-3
    strain = fibre_eigenstrain(np.tile([1.0, 0.0, 0.0], (len(tets), 1)), eps)
    uniform = eigenstrain_load(points, tets, E, 0.0, np.repeat(strain[:, None], n_samples, axis=1))
    assert np.allclose(uniform, eigenstrain_load(points, tets, E, 0.0, strain), rtol=0, atol=1e-12 * E)
    K = stiffness_matrix(points, tets, E, 0.0)
    inside = sample_points(points, tets[:, :4])[..., 0] < 0.3
    by_sample = strain[:, None] * inside[..., None, None]
    by_centroid = strain * (p1.mean(axis=1)[:, 0] < 0.3)[:, None, None]
    growth = {name: (extent(points, solve_static(K, eigenstrain_load(points, tets, E, 0.0, s),
                                                  fixed_dofs=minimal_supports(points)))[0] - L) / eps
              for name, s in (("samples", by_sample), ("centroids", by_centroid))}
    print(f"\nbar lengthened by eps times {growth} (exact 0.3 m)")
    assert growth["samples"] == pytest.approx(0.3, rel=0.05)  # 27 points place the edge to ~1/20 of an element
    assert growth["centroids"] == pytest.approx(0.25, rel=1e-6)
    with pytest.raises(HitogataError, match=r"eigenstrain has shape \(24, 3\)"):
        eigenstrain_load(points, tets, E, NU, np.zeros((24, 3)))
