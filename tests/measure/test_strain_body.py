"""Skin strain: analytic triangles, zero for rest and rigid motions, the bent elbow."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from measure_posing import flex_elbow

from hitogata.errors import HitogataError
from hitogata.measure.landmarks import body_landmarks
from hitogata.measure.strain import skin_strain
from hitogata.measure.zones import ZONE_NAMES, body_zones, zone_strains

TRIANGLE = np.array([[0.0, 0.0, 0.0], [0.02, 0.0, 0.0], [0.007, 0.015, 0.0]])
ONE = np.array([[0, 1, 2]])


def test_uniaxial_stretch_of_a_triangle():
    s = skin_strain(TRIANGLE, TRIANGLE * [1.2, 1.0, 1.0], ONE)
    assert s.stretch_max[0] == pytest.approx(1.2, rel=1e-12)
    assert s.stretch_min[0] == pytest.approx(1.0, rel=1e-12)
    assert s.area_ratio[0] == pytest.approx(1.2, rel=1e-12)
    assert abs(s.direction[0] @ [1.0, 0.0, 0.0]) == pytest.approx(1.0, rel=1e-12)


def test_simple_shear_of_a_tilted_triangle():
    gamma = 0.3
    shear = TRIANGLE + np.outer(TRIANGLE[:, 1], [gamma, 0.0, 0.0])
    turn = Rotation.from_rotvec([0.2, 0.9, -0.4]).as_matrix()
    s = skin_strain(TRIANGLE @ turn.T, shear @ turn.T, ONE)  # the triangle's plane is arbitrary
    root = np.sqrt(1 + gamma**2 / 4)
    assert s.stretch_max[0] == pytest.approx(root + gamma / 2, rel=1e-12)
    assert s.stretch_min[0] == pytest.approx(root - gamma / 2, rel=1e-12)
    assert s.area_ratio[0] == pytest.approx(1.0, rel=1e-12)  # shear keeps area


def test_rest_pose_has_no_strain(female):
    s = skin_strain(female.vertices, female.vertices, female.faces)
    assert np.all(s.stretch_max == 1.0) and np.all(s.stretch_min == 1.0) and np.all(s.area_ratio == 1.0)


@pytest.mark.parametrize("sex", ["female", "male"])
def test_rigid_motion_has_no_strain(sex, request):
    body = request.getfixturevalue(sex)
    turn = Rotation.from_rotvec([1.3, -0.4, 2.2]).as_matrix()
    moved = body.vertices @ turn.T + np.array([0.7, -1.5, 2.0])
    s = skin_strain(body.vertices, moved, body.faces)
    for values in (s.stretch_max, s.stretch_min, s.area_ratio):
        assert np.max(np.abs(values - 1.0)) < 1e-9
    assert all(abs(z.stretch_max) < 1e-7 for z in zone_strains(body, s).values())  # percent


def test_bent_elbow_stretches_most_over_the_back_of_the_elbow(female):
    # Elbow flexed to 120° by the posing code (tests/measure_posing.py).
    vertices, _ = flex_elbow(female, np.radians(120))
    s = skin_strain(female.vertices, vertices, female.faces)
    rig = female.rig
    elbow = rig.heads[rig.index("lowerarm01.R")]
    back = body_landmarks(female).olecranon.at(female.vertices) - elbow  # towards the olecranon
    worst = int(np.nanargmax(s.stretch_max))
    assert worst in set(body_zones(female)["elbow_right"])
    assert (female.vertices[female.faces[worst]].mean(axis=0) - elbow) @ back > 0
    # The back half of the elbow zone stretches more than the front half on average.
    zone = body_zones(female)["elbow_right"]
    side = (female.vertices[female.faces[zone]].mean(axis=1) - elbow) @ back
    area = s.rest_area[zone]
    behind = np.average(s.stretch_max[zone][side > 0], weights=area[side > 0])
    front = np.average(s.stretch_max[zone][side <= 0], weights=area[side <= 0])
    assert behind > front
    figures = zone_strains(female, s)
    assert figures["elbow_right"].stretch_max > 30.0
    assert all(figures[z].stretch_max == 0.0 for z in ZONE_NAMES if z != "elbow_right")


def test_zones_are_disjoint_and_mirror_each_other(male):
    zones = body_zones(male)
    assert set(zones) == set(ZONE_NAMES)
    seen = np.concatenate(list(zones.values()))
    assert len(np.unique(seen)) == len(seen)
    for part in ("shoulder", "elbow", "knee"):
        assert len(zones[f"{part}_left"]) == len(zones[f"{part}_right"]) > 100
    assert len(zones["back"]) > 300 and len(zones["seat"]) > 200


def test_mismatched_shapes_are_a_one_line_error(female):
    with pytest.raises(HitogataError, match="deformed vertices: shape"):
        skin_strain(female.vertices, female.vertices[:-1], female.faces)
