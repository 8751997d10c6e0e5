"""The shipped mobility scenarios: each loads, is on the whole body, names its sources, stays within the joint ranges."""

from __future__ import annotations

import numpy as np
import pytest

from hitogata.motion.scenario import load_scenario, shipped_scenarios
from hitogata.motion.clip import peak_clip, scenario_clip
from hitogata.posing import poser_for
from hitogata.skeleton.kinematics import limit_violations
from hitogata.skin.contact import GROUPS, skin_contact

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


@pytest.mark.parametrize("sex", ["female", "male"])
def test_no_peak_puts_a_forearm_or_hand_inside_another_part(request, sex):
    """A posture a person can take: at each motion's peak, the skinned forearms and hands lie at most 10 mm
    (soft tissue pressed) inside any part but their own arm.
    Crossed arms with both forearms at one height put each hand inside the other shoulder (25 mm and more
    deep, over 1,700 vertices): no contact solve can answer that, and the skin's then holds the hands flat
    against each other at the midline, 20 cm from their bones."""
    poser = poser_for(request.getfixturevalue(sex))
    test = skin_contact(poser)
    names = list(GROUPS)
    deep = {}
    for name in MOBILITY:
        angles = peak_clip(scenario_clip(load_scenario(shipped_scenarios()[name]), poser)).angles[1]
        found = test.penetrations(poser.pose_many(angles[None], "dqs")[0])
        for vertex, face, depth in zip(found.vertex, found.face, found.depth):
            inside, into = names[test.groups[vertex]], names[test.groups[test.faces[face, 0]]]
            if not inside.startswith(("forearm", "hand")):
                continue
            own_arm = into.startswith(("upper_arm", "forearm", "hand", "shoulder")) and into[-2:] == inside[-2:]
            if not own_arm:
                deep[(name, inside, into)] = max(deep.get((name, inside, into), 0.0), round(1e3 * depth, 1))
    assert all(mm <= 10.0 for mm in deep.values()), deep
