"""No dynamic-ease figure of the eight mobility motions lies outside what measured people allow: each
girth and length change of the default bodies (skinned and elastic) is within its plausible range
(`validation.envelope`), and the heights are undefined."""

from __future__ import annotations

import pytest

from hitogata.motion.scenario import load_scenario, shipped_scenarios
from hitogata.garment.ease import HEIGHTS, elastic_surface, motion_ease, skinned_surface
from hitogata.motion.clip import peak_clip, scenario_clip
from hitogata.posing import poser_for
from hitogata.validation import load_dataset
from hitogata.validation.envelope import allowed_change

MOTIONS = ("reach_forward", "arms_crossed", "arms_overhead", "sit", "deep_squat", "stride", "toe_touch",
           "trunk_twist")


@pytest.mark.slow
@pytest.mark.parametrize("sex", ["female", "male"])
def test_every_ease_figure_is_one_measured_people_allow(request, sex):
    body = request.getfixturevalue(sex)
    data = load_dataset()
    poser = poser_for(body)
    shipped = shipped_scenarios()
    outside = []
    for surface_name, surface in (("skinned", skinned_surface(body)), ("elastic", elastic_surface(body))):
        for motion in MOTIONS:
            clip = peak_clip(scenario_clip(load_scenario(shipped[f"mobility_{motion}"]), poser))
            for row in motion_ease(body, motion, clip, surface, rate=1.0).largest():
                name = row["measurement"]
                if name in HEIGHTS:
                    assert row["increase_cm"] is None and row["decrease_cm"] is None
                    continue
                allowed = allowed_change(data, name, row["standing_cm"] / 100)
                for change in (row["increase_cm"] / 100, row["decrease_cm"] / 100):
                    if not allowed.holds(change):
                        outside.append((surface_name, motion, name, round(100 * change, 1),
                                        round(100 * allowed.low, 1), round(100 * allowed.high, 1), allowed.basis))
    assert not outside, outside
