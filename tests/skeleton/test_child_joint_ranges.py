"""Children's ranges of motion: a six-year-old's limits are the adult skeleton's widened as Soucie et al.
(2011) measured, an adult's are the skeleton list's to the bit, and posing a child past its own range
is refused or clamped as an adult's is."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hitogata.body import Body
from hitogata.errors import HitogataError
from hitogata.muscles.activation import MuscleLimitWarning
from hitogata.posing.pose import Poser, shipped_lists
from hitogata.skeleton.child_ranges import load_child_ranges, with_age_ranges
from hitogata.skeleton.placement import Skeleton, place_skeleton

# The six-year-old's clinical limits (degrees) the data give, from the adult skeleton's AAOS limits:
# knee flexion 135 + (152.6 − 141.9) girls, 135 + (147.8 − 137.7) boys; hip flexion Soucie's mean;
# knee hyperextension Soucie's mean; ankle dorsiflexion 20 + (24.8 − 13.8), 20 + (22.8 − 12.7);
# glenohumeral flexion 120 + ⅔ (178.6 − 172.0), 120 + ⅔ (177.8 − 168.8).
EXPECTED = {
    "female": {("shank", "flexion", 1): 145.7, ("thigh", "flexion", 1): 140.8, ("shank", "flexion", 0): -5.4,
               ("foot", "dorsiflexion", 1): 31.0, ("upper_arm", "flexion", 1): 124.4},
    "male": {("shank", "flexion", 1): 145.1, ("thigh", "flexion", 1): 131.1, ("shank", "flexion", 0): -1.6,
             ("foot", "dorsiflexion", 1): 30.1, ("upper_arm", "flexion", 1): 126.0},
}
SHARE_ROUNDING = 0.01  # degrees: the file's ⅔ is 0.6667


def clinical_limits(sk: Skeleton) -> np.ndarray:
    """(D, 2) clinical lower and upper limits, degrees."""
    return np.degrees(np.stack([sk.lower + sk.rest, sk.upper + sk.rest], axis=1))


@pytest.fixture(scope="module", params=["female", "male"])
def six(request) -> tuple[str, Poser]:
    return request.param, Poser.from_body(Body.from_measurements(request.param, age=6))


def adult_skeleton(poser: Poser) -> Skeleton:
    """The skeleton list placed on the same body, without children's ranges."""
    return place_skeleton(shipped_lists()[0], poser.body.rig)


def test_six_year_olds_limits_are_the_data_s(six):
    sex, poser = six
    child, adult = clinical_limits(poser.skeleton), clinical_limits(adult_skeleton(poser))
    changed = np.zeros_like(child, dtype=bool)
    for (part, dof, end), degrees in EXPECTED[sex].items():
        for side in ("l", "r"):
            d = poser.skeleton.dof_index(f"{part}_{side}.{dof}")
            assert child[d, end] == pytest.approx(degrees, abs=SHARE_ROUNDING), (part, side, dof, end)
            assert abs(child[d, end]) > abs(adult[d, end])  # wider than the adult's
            changed[d, end] = True
    # hip extension: Soucie's 2-8 year mean (26.2° girls, 28.3° boys) lies inside the adult's 30°, kept
    assert child[poser.skeleton.dof_index("thigh_l.flexion"), 0] == adult[poser.skeleton.dof_index("thigh_l.flexion"), 0]
    np.testing.assert_array_equal(child[~changed], adult[~changed])


def test_adults_and_nine_year_olds_keep_the_skeleton_lists_limits(female, six):
    poser = Poser.from_body(female)
    listed = adult_skeleton(poser)
    np.testing.assert_array_equal(poser.skeleton.lower, listed.lower)
    np.testing.assert_array_equal(poser.skeleton.upper, listed.upper)
    table = load_child_ranges()
    child_skeleton = adult_skeleton(six[1])
    assert with_age_ranges(child_skeleton, 0.0, table.below_age) is child_skeleton
    assert with_age_ranges(child_skeleton, 0.0, 30.0) is child_skeleton
    assert with_age_ranges(child_skeleton, 0.0, table.from_age) is not child_skeleton


def test_posing_a_child_past_its_range_raises_or_clamps_as_an_adults(six, female):
    sex, poser = six
    knee_max = EXPECTED[sex][("shank", "flexion", 1)]
    # within the child's range, past the adult's 135°
    within = poser.angles(clinical={"shank_l.flexion": math.radians(knee_max - 2.0)})
    assert math.degrees(poser.skeleton.clinical(within)[poser.skeleton.dof_index("shank_l.flexion")]) == (
        pytest.approx(knee_max - 2.0, abs=1e-9))
    with pytest.raises(HitogataError, match="shank_l.flexion"):
        Poser.from_body(female).angles(clinical={"shank_l.flexion": math.radians(knee_max - 2.0)})
    # past the child's own range
    beyond = {"shank_l.flexion": math.radians(knee_max + 5.0)}
    with pytest.raises(HitogataError, match="shank_l.flexion"):
        poser.angles(clinical=beyond)
    with pytest.warns(MuscleLimitWarning, match="shank_l.flexion"):
        clamped = poser.angles(clinical=beyond, on_limit="clamp")
    d = poser.skeleton.dof_index("shank_l.flexion")
    assert math.degrees(poser.skeleton.clinical(clamped)[d]) == pytest.approx(knee_max, abs=SHARE_ROUNDING)
