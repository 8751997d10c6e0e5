"""The lattice mesher (isosurface stuffing) and its surface queries on shapes with known answers."""

import numpy as np
import pytest
import trimesh

from hitogata.geometry.mesh_checks import contains, is_closed, is_consistently_oriented
from hitogata.volume.domain import HalfSpace, Intersection, SurfaceDomain
from hitogata.volume.lattice import stuff
from hitogata.volume.quality import boundary_faces, dihedral_angles, signed_volumes, surface_distances
from hitogata.volume.surface import SurfaceIndex

RADIUS = 0.1
# The stencils' angle bound proved by Labelle & Shewchuk (2007) for their parity rule;
# our diagonal rule is measured against it (see lattice.py).
MIN_DIHEDRAL_FLOOR = 10.7


@pytest.fixture(scope="module")
def sphere():
    s = trimesh.creation.icosphere(subdivisions=5, radius=RADIUS)
    return np.asarray(s.vertices), np.asarray(s.faces)


def mesh(vertices, faces, h):
    domain = SurfaceDomain(vertices, faces)
    return domain, stuff(domain, h, (vertices.min(axis=0), vertices.max(axis=0)))


def polyhedron_volume(vertices, faces):
    return float(trimesh.Trimesh(vertices, faces, process=False).volume)


def test_surface_index_contains_matches_winding_number(sphere):
    v, f = sphere
    points = np.random.default_rng(0).uniform(-1.2 * RADIUS, 1.2 * RADIUS, (400, 3))
    index = SurfaceIndex(v, f)
    assert np.array_equal(index.contains(points), contains(v, f, points))


def test_surface_index_ray_through_vertices_and_edges_counts_once():
    box = trimesh.creation.box(extents=(1.0, 1.0, 1.0)).subdivide()
    index = SurfaceIndex(np.asarray(box.vertices), np.asarray(box.faces))
    # Through an inner vertex of the top and bottom faces, along inner edges, inside triangles.
    inner = np.array([[0.0, 0.0], [0.25, 0.0], [0.0, -0.25], [0.25, 0.25], [0.1, 0.3]])
    ptr, z = index.crossings_z(inner)
    assert np.diff(ptr).tolist() == [2] * len(inner)
    assert np.allclose(z, np.tile([-0.5, 0.5], len(inner)))
    # On the silhouette (the side faces are vertical) a line counts 0 or 2, never 1.
    ptr, _ = index.crossings_z(np.array([[0.5, 0.5], [0.5, 0.0], [-0.5, 0.2], [0.0, 0.5]]))
    assert np.all(np.diff(ptr) % 2 == 0)


def test_surface_index_crossing_and_distance_on_sphere(sphere):
    v, f = sphere
    index = SurfaceIndex(v, f)
    rng = np.random.default_rng(1)
    directions = rng.normal(size=(200, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    t = index.first_crossing(np.zeros((200, 3)), 2 * RADIUS * directions)
    # The icosphere's facets lie inside the sphere by at most ~0.03% of its radius here.
    assert np.allclose(t * 2 * RADIUS, RADIUS, atol=4e-4 * RADIUS)
    depth = rng.uniform(0.1, 0.9, 200)
    points = directions * depth[:, None] * RADIUS
    assert np.allclose(index.distance(points), (1 - depth) * RADIUS, atol=4e-4 * RADIUS)


@pytest.mark.parametrize("h", [0.04, 0.02, 0.01])
def test_sphere_mesh_is_valid_and_follows_the_surface(sphere, h):
    v, f = sphere
    domain, m = mesh(v, f, h)
    volumes = signed_volumes(m.nodes, m.tets)
    assert volumes.min() > 0
    assert np.degrees(dihedral_angles(m.nodes, m.tets)).min() >= MIN_DIHEDRAL_FLOOR
    faces, _ = boundary_faces(m.tets)
    assert is_closed(faces) and is_consistently_oriented(faces)
    # Every boundary node lies on the surface.
    assert np.all(m.node_part[np.unique(faces)] == 0)
    forward, backward = surface_distances(m.nodes, faces, domain.index, v)
    assert max(forward.max(), backward.max()) <= 0.1 * h
    # Chords cut the curved surface: the volume error is of order (h / R)².
    error = volumes.sum() / polyhedron_volume(v, f) - 1
    assert -3.0 * (h / RADIUS) ** 2 < error <= 0.0


def test_volume_error_converges_quadratically(sphere):
    v, f = sphere
    reference = polyhedron_volume(v, f)
    errors = [abs(signed_volumes(*(lambda m: (m.nodes, m.tets))(mesh(v, f, h)[1])).sum() / reference - 1)
              for h in (0.04, 0.02, 0.01)]
    assert errors[0] > errors[1] > errors[2]
    rates = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(rates > 1.5)


def test_cut_box_volume_and_cut_plane():
    box = trimesh.creation.box(extents=(0.3, 0.2, 0.25))
    box.apply_transform(trimesh.transformations.rotation_matrix(0.4, [1, 2, 3]))
    v, f = np.asarray(box.vertices), np.asarray(box.faces)
    cut = HalfSpace(np.zeros(3), np.array([0.0, 1.0, 0.0]), "cut")
    domain = Intersection(SurfaceDomain(v, f), cut)
    m = stuff(domain, 0.02, (v.min(axis=0), v.max(axis=0)))
    assert signed_volumes(m.nodes, m.tets).min() > 0
    assert np.degrees(dihedral_angles(m.nodes, m.tets)).min() >= MIN_DIHEDRAL_FLOOR
    # Half the box by symmetry (the plane passes through its centre); edges and corners
    # are rounded off by about an element.
    error = signed_volumes(m.nodes, m.tets).sum() / (0.5 * 0.3 * 0.2 * 0.25) - 1
    assert -0.05 < error <= 0.0
    on_cut = m.node_part == 1
    assert on_cut.any() and np.allclose(m.nodes[on_cut, 1], 0.0, atol=1e-12)
    assert np.all(m.nodes[:, 1] <= 1e-12)


def test_mesher_is_deterministic(sphere):
    v, f = sphere
    a, b = mesh(v, f, 0.02)[1], mesh(v, f, 0.02)[1]
    assert np.array_equal(a.nodes, b.nodes) and np.array_equal(a.tets, b.tets)
