"""Every body the shape supports can be posed: the skeleton and muscles place on all of them."""

import itertools
import warnings

import numpy as np
import pytest

from hitogata.body import Body
from hitogata.muscles.geometry import MuscleGeometryWarning
from hitogata.posing import pose_body

POPULATION = [
    (sex, age, stature, bmi)
    for sex, age, stature, bmi in itertools.product(("female", "male"), (25, 70), (1.45, 1.65, 1.95), (18, 30))
]


@pytest.mark.parametrize("sex,age,stature,bmi", POPULATION)
def test_every_supported_body_poses(sex: str, age: float, stature: float, bmi: float) -> None:
    body = Body.from_measurements(sex, age, stature, bmi * stature**2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MuscleGeometryWarning)  # old bodies' forward-leaning necks
        posed = pose_body(body, clinical={"forearm_r.flexion": np.radians(120.0)})
    assert np.all(np.isfinite(posed.vertices))
    assert posed.angle("forearm_r.flexion") != 0.0
