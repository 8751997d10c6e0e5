"""Issue 12's extreme poses (`hitogata.skeleton.extreme_poses`) held by the elastic body with its
self-contact resolved (`elastic_pose(..., contact=True)`), on both default bodies: the skin passes
nowhere through itself, no vertex lies inside another part, no element inverts and the body keeps
its volume."""

from __future__ import annotations

import numpy as np
import pytest

from hitogata.dynamics.single_pose import elastic_dynamics, elastic_pose
from hitogata.geometry import enclosed_volume, self_intersections
from hitogata.skeleton.extreme_poses import extreme_poses

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module", params=["female", "male"])
def held(request):
    """The body's name, its rest skin and every extreme pose held with contact."""
    body = request.getfixturevalue(request.param)
    dynamics = elastic_dynamics(body)
    poses = {name: elastic_pose(dynamics, clinical=clinical, contact=True)
             for name, clinical in extreme_poses(dynamics.poser.skeleton).items()}
    return request.param, body, poses


def test_the_skin_stays_whole_and_the_body_keeps_its_volume(held):
    sex, body, poses = held
    rest_pairs = set(map(tuple, self_intersections(body.vertices, body.faces).tolist()))
    rest_volume = enclosed_volume(body.vertices, body.faces)
    figures = {}
    for name, pose in poses.items():
        crossing = set(map(tuple, self_intersections(pose.vertices, body.faces).tolist())) - rest_pairs
        inside = pose.penetrations
        figures[name] = (len(crossing), len(inside), round(inside.deepest * 1e3, 1), pose.quality.inverted,
                         round((enclosed_volume(pose.vertices, body.faces) / rest_volume - 1) * 100, 2))
    print(sex, figures)
    for name, (crossing, inside, deepest, inverted, volume) in figures.items():
        assert crossing == 0 and deepest <= 2.0 and inverted == 0 and abs(volume) < 1.0, (name, figures[name])
