"""Soft tissue meshed round bone capsules: a capsule in a sphere, then the trunk's bones at several sizes."""

import numpy as np
import pytest
import trimesh

from hitogata.elastic import assemble_system, build_elastic_model
from hitogata.errors import HitogataError
from hitogata.volume import build_trunk_model, build_volume_model
from hitogata.volume.anatomy import BONE_MIN_RADIUS
from hitogata.volume.bones import PART, attach_surface_nodes, capsule_gap, held_volume, outside_capsules
from hitogata.volume.domain import Intersection, SurfaceDomain
from hitogata.volume.lattice import stuff
from hitogata.volume.quality import boundary_faces, signed_volumes

HEADS = np.array([[-0.05, 0.0, 0.0]])
TAILS = np.array([[0.05, 0.0, 0.0]])
RADII = np.array([0.02])
CAPSULE_VOLUME = np.pi * 0.02**2 * 0.1 + 4.0 / 3.0 * np.pi * 0.02**3


@pytest.fixture(scope="module")
def ball():
    s = trimesh.creation.icosphere(subdivisions=5, radius=0.12)
    return SurfaceDomain(np.asarray(s.vertices), np.asarray(s.faces))


def test_held_volume_is_the_capsules_volume_inside_the_domain(ball):
    assert held_volume(ball, HEADS, TAILS, RADII, 0.001) == pytest.approx(CAPSULE_VOLUME, rel=0.01)
    # Two overlapping capsules count their common part once.
    twice = held_volume(ball, np.repeat(HEADS, 2, axis=0), np.repeat(TAILS, 2, axis=0), np.repeat(RADII, 2), 0.001)
    assert twice == pytest.approx(CAPSULE_VOLUME, rel=0.01)


@pytest.mark.parametrize("h, least", [(0.02, 0.85), (0.01, 0.96)])
def test_the_mesh_leaves_the_capsule_out_and_its_surface_nodes_hold_it(ball, h, least):
    domain = Intersection(ball, outside_capsules(HEADS, TAILS, RADII))
    mesh = stuff(domain, h, (np.full(3, -0.12), np.full(3, 0.12)))
    assert signed_volumes(mesh.nodes, mesh.tets).min() > 0
    held, bone = attach_surface_nodes(mesh.nodes, mesh.node_part, domain.parts.index(PART), HEADS, TAILS, RADII)
    assert len(held) > 20 and np.all(bone == 0)
    assert np.abs(capsule_gap(mesh.nodes[held], HEADS, TAILS, RADII)).max() < 1e-9  # on the surface
    assert capsule_gap(mesh.nodes, HEADS, TAILS, RADII).min() > -1e-9  # no node inside
    # The hole is a polyhedron inscribed in the capsule: the finer, the closer its volume
    # (88 % of it at h = r, 97 % at h = r / 2; only 11 % at h = 2 r).
    faces, _ = boundary_faces(mesh.tets)
    around = faces[np.all(mesh.node_part[faces] == domain.parts.index(PART), axis=1)]
    p = mesh.nodes[around]
    hole = -np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0  # faces point into the hole
    assert least * CAPSULE_VOLUME < hole < CAPSULE_VOLUME


def test_trunk_bones_are_the_same_at_every_size(female):
    held = [build_trunk_model(female, size).quality.held_volume for size in (40.0, 25.0)]
    assert held[0] == pytest.approx(held[1], rel=0.05)
    assert BONE_MIN_RADIUS == 0.020


def test_elastic_bone_uses_labelled_bone_tets(female):
    model = build_elastic_model(female, element_size=60.0, n_modes=4, bone="elastic")
    assert np.any(model.region == model.region_names.index("bone"))
    conforming = build_volume_model(female.vertices, female.faces, female.rig, female.skin_weights, bmi=female.bmi,
                                    sex=female.params.sex, element_size=60.0)
    with pytest.raises(HitogataError, match="bones='labelled'"):
        assemble_system(conforming, female.rig, bone="elastic")
    with pytest.raises(HitogataError, match="bones"):
        build_volume_model(female.vertices, female.faces, female.rig, female.skin_weights, bmi=female.bmi,
                           sex=female.params.sex, bones="fused")
