"""Tests for hitogata.geometry.mesh_checks on shapes with known answers."""

import numpy as np
import pytest
import trimesh

from hitogata.geometry import mesh_checks as mc
from hitogata.geometry.broad_phase import box_pairs


@pytest.fixture(scope="module")
def sphere() -> trimesh.Trimesh:
    return trimesh.creation.icosphere(subdivisions=3, radius=1.0)


@pytest.fixture(scope="module")
def cube() -> trimesh.Trimesh:
    return trimesh.creation.box(extents=(1.0, 1.0, 1.0))


def merged(*meshes: trimesh.Trimesh) -> tuple[np.ndarray, np.ndarray]:
    """Concatenate meshes into one vertex/face array pair without welding."""
    vertices, faces, offset = [], [], 0
    for m in meshes:
        vertices.append(m.vertices)
        faces.append(m.faces + offset)
        offset += len(m.vertices)
    return np.concatenate(vertices), np.concatenate(faces)


# --------------------------------------------------------------------------- topology


@pytest.mark.parametrize("name", ["sphere", "cube"])
def test_closed_shapes_are_closed_and_oriented(name, request):
    m = request.getfixturevalue(name)
    assert mc.is_closed(m.faces)
    assert mc.is_consistently_oriented(m.faces)
    assert len(mc.boundary_edges(m.faces)) == 0
    assert mc.connected_component_count(m.faces) == 1
    assert mc.euler_characteristic(m.faces) == 2
    assert mc.genus(m.faces) == 0


def test_open_patch_has_boundary(cube):
    faces = cube.faces[2:]
    assert not mc.is_closed(faces)
    assert mc.is_consistently_oriented(faces)
    assert len(mc.boundary_edges(faces)) == 4
    with pytest.raises(ValueError, match="closed"):
        mc.genus(faces)


def test_flipped_face_is_detected(sphere):
    faces = sphere.faces.copy()
    faces[17] = faces[17, ::-1]
    assert mc.is_closed(faces)
    assert not mc.is_consistently_oriented(faces)


def test_torus_genus_and_two_components(sphere):
    torus = trimesh.creation.torus(major_radius=1.0, minor_radius=0.3)
    assert mc.genus(torus.faces) == 1
    v, f = merged(sphere, torus)
    assert mc.connected_component_count(f) == 2
    assert mc.genus(f) == 1


def test_volume_cube_and_sphere(cube, sphere):
    assert mc.enclosed_volume(cube.vertices, cube.faces) == pytest.approx(1.0, rel=1e-12)
    fine = trimesh.creation.icosphere(subdivisions=5, radius=0.5)
    assert mc.enclosed_volume(fine.vertices, fine.faces) == pytest.approx(4 / 3 * np.pi * 0.125, rel=2e-3)
    assert mc.enclosed_volume(sphere.vertices, sphere.faces[:, ::-1]) < 0


# --------------------------------------------------------------------------- winding number


def test_winding_number_inside_outside(cube, sphere):
    rng = np.random.default_rng(1)
    points = rng.uniform(-1.5, 1.5, size=(400, 3))
    for m in (cube, sphere):
        w = mc.winding_number(m.vertices, m.faces, points)
        # a point's side, decided away from the surface where it is unambiguous
        if m is cube:
            inside = np.all(np.abs(points) < 0.5, axis=1)
            clear = np.abs(np.abs(points).max(axis=1) - 0.5) > 1e-3
        else:
            r = np.linalg.norm(points, axis=1)
            inside, clear = r < 0.99, (r < 0.98) | (r > 1.0)
        assert np.allclose(w[clear], inside[clear].astype(float), atol=1e-9)
        assert np.array_equal(mc.contains(m.vertices, m.faces, points)[clear], inside[clear])


def test_winding_number_counts_nested_and_inverted(sphere):
    small = trimesh.creation.icosphere(subdivisions=2, radius=0.5)
    v, f = merged(sphere, small)
    w = mc.winding_number(v, f, [[0, 0, 0], [0.75, 0, 0], [2, 0, 0]])
    assert np.allclose(w, [2, 1, 0], atol=1e-9)
    w = mc.winding_number(sphere.vertices, sphere.faces[:, ::-1], [[0, 0, 0]])
    assert w[0] == pytest.approx(-1.0)


# --------------------------------------------------------------------------- self-intersection


def test_single_sphere_has_no_self_intersections(sphere):
    assert mc.self_intersections(sphere.vertices, sphere.faces).shape == (0, 2)


def test_interpenetrating_cubes_intersect(cube):
    other = cube.copy()
    other.apply_translation([0.4, 0.3, 0.2])
    v, f = merged(cube, other)
    pairs = mc.self_intersections(v, f)
    assert len(pairs) > 0
    assert np.all(pairs[:, 0] < pairs[:, 1])
    # every reported pair crosses from one cube to the other
    assert np.all((pairs[:, 0] < 12) & (pairs[:, 1] >= 12))


def test_separate_cubes_do_not_intersect(cube):
    other = cube.copy()
    other.apply_translation([1.2, 0.0, 0.0])
    v, f = merged(cube, other)
    assert len(mc.self_intersections(v, f)) == 0


def test_neighbours_touching_at_a_shared_vertex_are_not_reported():
    # Two triangles meeting only at vertex 0 and two meeting along edge 0-1.
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [-1, 0, 0.5], [0.5, -1, 0.5]], float)
    assert len(mc.self_intersections(vertices, [[0, 1, 2], [0, 3, 4]])) == 0
    assert len(mc.self_intersections(vertices, [[0, 1, 2], [0, 1, 3]])) == 0
    # The same geometry with the vertex duplicated (unwelded) touches: reported.
    vertices = np.vstack([vertices, vertices[:1]])
    assert mc.self_intersections(vertices, [[0, 1, 2], [6, 3, 4]]).tolist() == [[0, 1]]


def test_pushed_vertex_folding_through_the_surface_is_detected(sphere):
    v = sphere.vertices.copy()
    v[0] = -1.3 * v[0]  # dragged through the body and out the other side
    pairs = mc.self_intersections(v, sphere.faces)
    fan = np.flatnonzero((sphere.faces == 0).any(axis=1))
    assert len(pairs) > 0
    assert np.all(np.isin(pairs, fan).any(axis=1))


def test_local_fold_through_a_thin_part_is_detected():
    slab = trimesh.creation.box(extents=(1.0, 0.1, 1.0)).subdivide().subdivide().subdivide()
    v = slab.vertices.copy()
    k = np.argmin(np.linalg.norm(v - [0.0, 0.05, 0.0], axis=1))
    v[k, 1] -= 0.15  # a top vertex pushed in and out through the bottom face
    assert len(mc.self_intersections(slab.vertices, slab.faces)) == 0
    pairs = mc.self_intersections(v, slab.faces)
    fan = np.flatnonzero((slab.faces == k).any(axis=1))
    assert len(pairs) > 0
    assert np.all(np.isin(pairs, fan).any(axis=1))


def test_coplanar_overlap_and_separation():
    square = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    shifted = square + [0.2, 0.2, 0.0]
    far = square + [2.0, 0.0, 0.0]
    inside = 0.1 * square + [0.2, 0.2, 0.0]
    for other, expected in ((shifted, 1), (far, 0), (inside, 1)):
        v = np.vstack([square, other])
        assert len(mc.self_intersections(v, [[0, 1, 2], [3, 4, 5]])) == expected


def _edge_hits_triangle(p: np.ndarray, q: np.ndarray, tri: np.ndarray) -> bool:
    """Reference test: does segment pq cross triangle tri (barycentric solve)?"""
    m = np.column_stack([tri[1] - tri[0], tri[2] - tri[0], p - q])
    u, v, t = np.linalg.solve(m, p - tri[0])
    return u >= 0 and v >= 0 and u + v <= 1 and 0 <= t <= 1


def test_random_pairs_match_edge_crossing_reference():
    # Two non-coplanar triangles meet iff an edge of one crosses the other.
    rng = np.random.default_rng(7)
    pairs = rng.normal(size=(400, 2, 3, 3))
    vertices = pairs.reshape(-1, 3)
    faces = np.arange(len(vertices)).reshape(-1, 3)
    found = {tuple(p) for p in mc.self_intersections(vertices, faces).tolist()}
    for k, (a, b) in enumerate(pairs):
        expected = any(_edge_hits_triangle(s[e], s[(e + 1) % 3], t) for s, t in ((a, b), (b, a)) for e in range(3))
        assert ((2 * k, 2 * k + 1) in found) == expected


def test_a_large_closed_mesh_has_no_self_intersections_and_contains_its_inside():
    """Correctness on a ~27k-face mesh; its speed is benchmarks/bench_mesh_checks.py's."""
    m = trimesh.creation.capsule(height=1.0, radius=0.2, count=[116, 116])
    assert 25_000 < len(m.faces) < 30_000
    points = np.random.default_rng(0).uniform(-0.3, 0.8, size=(300, 3))
    assert len(mc.self_intersections(m.vertices, m.faces)) == 0
    inside = mc.contains(m.vertices, m.faces, points)
    # the capsule: within 0.2 m of the segment from z=-0.5 to z=0.5 (trimesh's axis)
    t = np.clip(points[:, 2], -0.5, 0.5)
    distance = np.linalg.norm(points - np.c_[np.zeros((len(points), 2)), t], axis=1)
    clear = np.abs(distance - 0.2) > 0.005  # away from the faceted surface
    np.testing.assert_array_equal(inside[clear], distance[clear] < 0.2)


def test_broad_phase_finds_exactly_the_overlapping_boxes():
    rng = np.random.default_rng(3)
    lo = rng.uniform(0, 1, size=(300, 3))
    size = rng.lognormal(-4, 1, size=(300, 3))
    size[0] = 0.8  # one box much larger than the rest
    hi = lo + size
    i, j = box_pairs(lo, hi)
    overlap = np.all((lo[:, None] <= hi[None]) & (lo[None] <= hi[:, None]), axis=2)
    expected = set(zip(*np.nonzero(np.triu(overlap, 1))))
    assert set(zip(i.tolist(), j.tolist())) == expected
    assert len(i) == len(expected)  # each pair once


def test_edge_graph_measures_along_the_surface():
    """A unit cube's surface: each edge once, at its length; the way from one corner to the opposite one over
    the faces runs along a face's diagonal and an edge (√2 + 1), not through the cube (√3)."""
    from scipy.sparse.csgraph import dijkstra

    cube = trimesh.creation.box(extents=(1.0, 1.0, 1.0))
    graph = mc.edge_graph(cube.vertices, cube.faces)
    assert graph.nnz == len(cube.edges_unique) == 18
    assert sorted(set(np.round(graph.data, 12).tolist())) == [1.0, round(np.sqrt(2.0), 12)]
    start = int(np.argmin(cube.vertices.sum(axis=1)))
    far = int(np.argmax(cube.vertices.sum(axis=1)))
    assert dijkstra(graph, directed=False, indices=start)[far] == pytest.approx(np.sqrt(2.0) + 1.0)
