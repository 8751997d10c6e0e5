"""Fabric stretch per garment zone: zero on a rigid motion; across the back on reach-forward; the knee in sitting."""

from __future__ import annotations

import numpy as np
import pytest
from test_garment_ease import rigid_clip

from hitogata.motion.scenario import load_scenario, shipped_scenarios
from hitogata.garment.stretch import GARMENT_ZONES, directional_strain, stretch_csv, zone_stretch
from hitogata.motion.clip import scenario_clip
from hitogata.posing import poser_for
from hitogata.garment.stretch import garment_zones


def test_directional_strain_of_a_stretched_triangle():
    rest = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    posed = rest * [1.2, 0.9, 1.0]  # 20 % along x, −10 % along y
    faces = np.array([[0, 1, 2]])
    assert directional_strain(rest, posed, faces, np.array([[1.0, 0, 0]])) == pytest.approx([0.2])
    assert directional_strain(rest, posed, faces, np.array([[0.0, 1, 0]])) == pytest.approx([-0.1])


@pytest.mark.parametrize("sex", ["female", "male"])
def test_zones_exist_and_a_rigid_motion_stretches_nothing(request, sex):
    body = request.getfixturevalue(sex)
    zones, along = garment_zones(body)
    assert tuple(zones) == GARMENT_ZONES and all(len(f) > 50 for f in zones.values())
    assert np.allclose(np.linalg.norm(along, axis=1), 1.0)
    result = zone_stretch(body, "rigid", rigid_clip(poser_for(body).skeleton.n_dofs), rate=2.0)
    for values in (result.lengthwise, result.crosswise, result.principal, result.lengthwise_min, result.crosswise_min):
        assert np.abs(values).max() < 1e-6  # percent


@pytest.mark.parametrize("sex", ["female", "male"])
def test_reach_stretches_the_back_crosswise_and_sitting_the_knee_lengthwise(request, sex):
    body = request.getfixturevalue(sex)
    poser = poser_for(body)
    reach = zone_stretch(body, "reach", scenario_clip(load_scenario(shipped_scenarios()["mobility_reach_forward"]),
                                                      poser), rate=2.5)
    rows = {r["zone"]: r for r in reach.rows()}
    assert rows["across_back"]["crosswise_pct"] > 20
    assert rows["across_front"]["crosswise_min_pct"] < -5
    assert rows["knee"]["principal_pct"] == pytest.approx(0.0, abs=1e-6)  # the legs do not move
    sit = zone_stretch(body, "sit", scenario_clip(load_scenario(shipped_scenarios()["mobility_sit"]), poser), rate=2.5)
    rows = {r["zone"]: r for r in sit.rows()}
    assert rows["knee"]["lengthwise_pct"] > rows["knee"]["crosswise_pct"] > 0
    assert rows["seat"]["lengthwise_pct"] > 30
    assert stretch_csv([reach, sit]).count("\n") == 1 + 2 * len(GARMENT_ZONES)
