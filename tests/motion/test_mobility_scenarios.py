"""The shipped mobility scenarios: each loads, is on the whole body, names its sources, stays within the joint ranges."""

from __future__ import annotations

import numpy as np
import pytest

from hitogata.motion.scenario import load_scenario, shipped_scenarios
from hitogata.motion.clip import scenario_clip
from hitogata.posing import poser_for
from hitogata.skeleton.kinematics import limit_violations

MOBILITY = ("mobility_arms_overhead", "mobility_reach_forward", "mobility_arms_crossed", "mobility_sit",
            "mobility_deep_squat", "mobility_stride", "mobility_toe_touch", "mobility_trunk_twist")


@pytest.mark.parametrize("name", MOBILITY)
@pytest.mark.parametrize("sex", ["female", "male"])
def test_mobility_scenario_loads_within_the_joint_ranges(request, name, sex):
    path = shipped_scenarios()[name]
    scenario = load_scenario(path)
    assert scenario.model.extent == "body"
    assert "Sources:" in path.read_text() and scenario.title.startswith("mobility: ")
    poser = poser_for(request.getfixturevalue(sex))
    keys = sorted({t for c in scenario.timeline.channels for t in c.times})
    clip = scenario_clip(scenario, poser)  # on_limit = "raise": an angle beyond its range is an error
    assert not limit_violations(poser.skeleton, clip.angles).any()
    at_keys = np.isin(np.round(clip.times, 6), np.round(keys, 6))
    assert at_keys.sum() == len(keys)  # every keyframe is a frame, so its pose was checked
    assert np.degrees(np.abs(clip.angles).max()) > 20  # it moves


def test_the_poses_do_what_their_names_say(female):
    poser = poser_for(female)
    sk = poser.skeleton

    def peak(name: str, time: float) -> np.ndarray:
        scenario = load_scenario(shipped_scenarios()[name])
        clip = scenario_clip(scenario, poser)
        k = int(np.argmin(np.abs(clip.times - time)))
        return poser.kinematics.pose(clip.angles[k]).joints[0]

    crossed = peak("mobility_arms_crossed", 1.5)
    assert crossed[sk.index("hand_l"), 0] < 0 < crossed[sk.index("hand_r"), 0]  # each hand past the midline
    overhead = peak("mobility_arms_overhead", 1.5)
    assert overhead[sk.index("hand_l"), 1] > overhead[sk.index("head"), 1] + 0.25
    reach = peak("mobility_reach_forward", 1.5)
    assert abs(reach[sk.index("hand_l"), 1] - reach[sk.index("upper_arm_l"), 1]) < 0.05  # at shoulder height
    assert reach[sk.index("hand_l"), 2] > 0.4  # in front
    sit = peak("mobility_sit", 1.5)
    thigh = sit[sk.index("shank_r")] - sit[sk.index("thigh_r")]
    assert abs(np.degrees(np.arctan2(thigh[1], thigh[2]))) < 10  # the thigh level
