"""P1/P2 tetrahedra: quadrature, shape functions, P2 construction, boundary faces, box mesher."""

from math import factorial

import numpy as np
import pytest

from hitogata.fem.verify.box_mesh import box_mesh
from hitogata.fem.elements import (
    P2_EDGES,
    boundary_triangles,
    lift_node_set,
    p2_mesh,
    quadrature,
    reference_mass,
    shape_derivatives,
    shape_gradients,
    shape_values,
    tet_geometry,
)


def exact_monomial(powers):
    """Integral of L0^a L1^b L2^c L3^d over a tet, divided by its volume: 3! a! b! c! d! / (a+b+c+d+3)!."""
    return 6.0 * np.prod([factorial(p) for p in powers]) / factorial(sum(powers) + 3)


@pytest.mark.parametrize("degree", [1, 2, 3, 4, 5, 6])
def test_quadrature_is_exact_up_to_its_degree(degree):
    bary, w = quadrature(degree)
    assert w.sum() == pytest.approx(1.0, abs=1e-14)
    for powers in [(degree, 0, 0, 0), (0, degree - 1, 1, 0), (1, 0, 0, degree - 1), (0, 1, degree // 2, degree - 1 - degree // 2)]:
        got = w @ np.prod(bary ** np.array(powers), axis=1)
        assert got == pytest.approx(exact_monomial(powers), rel=1e-13)


@pytest.mark.parametrize("order", [1, 2])
def test_shape_functions_interpolate_nodes_and_sum_to_one(order):
    corners = np.eye(4)
    mids = 0.5 * (corners[P2_EDGES[:, 0]] + corners[P2_EDGES[:, 1]])
    nodes = corners if order == 1 else np.vstack([corners, mids])
    assert np.allclose(shape_values(order, nodes), np.eye(len(nodes)), atol=1e-15)
    bary, _ = quadrature(4)
    assert np.allclose(shape_values(order, bary).sum(axis=1), 1.0)
    # sum of N is constant, so its derivative is the same along every L_k (gradients of L sum to 0)
    dsum = shape_derivatives(order, bary).sum(axis=1)
    assert np.allclose(dsum, dsum[:, :1])


def test_p2_gradients_match_finite_differences():
    x = np.array([[0, 0, 0], [1, 0.1, 0], [0.2, 1, 0.1], [0.1, 0.3, 1.2]])
    grads_l, vol = tet_geometry(x, np.array([[0, 1, 2, 3]]))
    assert vol[0] > 0
    point = x.T @ np.array([0.1, 0.2, 0.3, 0.4])

    def values(p):
        lam = np.linalg.solve(np.vstack([x.T, np.ones(4)]), np.append(p, 1.0))
        return shape_values(2, lam)[0]

    lam0 = np.linalg.solve(np.vstack([x.T, np.ones(4)]), np.append(point, 1.0))
    g = shape_gradients(2, lam0[None], grads_l)[0, 0]  # (10, 3)
    h = 1e-6
    fd = np.stack([(values(point + h * e) - values(point - h * e)) / (2 * h) for e in np.eye(3)], axis=1)
    assert np.allclose(g, fd, atol=1e-7)
    assert np.allclose(g.sum(axis=0), 0.0, atol=1e-12)


def test_reference_mass_integrates_to_one():
    for order in (1, 2):
        assert reference_mass(order).sum() == pytest.approx(1.0, rel=1e-14)
    # known P1 values: V/10 on the diagonal, V/20 off it
    assert np.allclose(reference_mass(1), (np.ones((4, 4)) + np.eye(4)) / 20.0)


def test_box_mesh_volume_orientation_and_p2_nodes():
    points, tets = box_mesh((1.0, 0.1, 0.2), (5, 2, 3))
    assert len(points) == 6 * 3 * 4 and len(tets) == 6 * 5 * 2 * 3
    _, vol = tet_geometry(points, tets)
    assert np.all(vol > 0)
    assert vol.sum() == pytest.approx(0.02, rel=1e-13)
    p2, t2 = p2_mesh(points, tets)
    edges = {tuple(sorted(e)) for t in tets for e in t[P2_EDGES]}
    assert len(p2) == len(points) + len(edges)
    assert np.allclose(p2[:len(points)], points)
    assert np.allclose(p2[t2[:, 4:]], 0.5 * (points[tets[:, P2_EDGES[:, 0]]] + points[tets[:, P2_EDGES[:, 1]]]))


@pytest.mark.parametrize("order", [1, 2])
def test_boundary_faces_cover_the_surface_outward(order):
    points, tets = box_mesh((1.0, 0.1, 0.2), (4, 2, 3))
    if order == 2:
        points, tets = p2_mesh(points, tets)
    faces = boundary_triangles(tets)
    assert faces.shape[1] == (3 if order == 1 else 6)
    x = points[faces[:, :3]]
    normal = 0.5 * np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    assert np.linalg.norm(normal, axis=1).sum() == pytest.approx(2 * (0.1 + 0.2 + 0.02), rel=1e-13)
    assert np.allclose(normal.sum(axis=0), 0.0, atol=1e-14)  # closed surface
    outward = np.einsum("ij,ij->i", normal, x.mean(axis=1) - np.array([0.5, 0.05, 0.1]))
    assert np.all(outward > 0)
    if order == 2:
        mids = 0.5 * (points[faces[:, [0, 1, 2]]] + points[faces[:, [1, 2, 0]]])
        assert np.allclose(points[faces[:, 3:]], mids)


def test_lift_node_set_adds_midpoints_between_fixed_nodes_only():
    points, tets = box_mesh((1.0, 0.1, 0.1), (3, 1, 1))
    fixed = np.flatnonzero(points[:, 0] == 0.0)
    p2, t2 = p2_mesh(points, tets)
    lifted = lift_node_set(t2, fixed)
    assert set(fixed) <= set(lifted)
    assert np.array_equal(np.sort(lifted), np.flatnonzero(p2[:, 0] == 0.0))
