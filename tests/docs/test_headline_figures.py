"""The shipped model's headline figures, pinned to values: a change that moves them must say so here.

Measured with this tree (docs/measurements.md, docs/elastic.md). The whole body's
frequencies are pinned with the whole-body model's tests; here the default trunk.
"""

import pytest

from hitogata.body import default_body
from hitogata.elastic import build_elastic_model
from hitogata.measure import measure

# ISO 8559-1 measurements of the default bodies at rest, metres.
MEASUREMENTS = {
    "female": {
        "stature": 1.65, "neck_girth": 0.29572, "chest_girth": 0.92595, "underbust_girth": 0.78845,
        "waist_girth": 0.73771, "omphalion_waist_girth": 0.81908, "hip_girth": 1.01733, "thigh_girth": 0.62138,
        "upper_arm_girth": 0.28896, "armscye_girth": 0.45467, "knee_girth": 0.35779, "calf_girth": 0.36753,
        "ankle_girth": 0.19003, "wrist_girth": 0.13402, "back_waist_length": 0.39394, "across_back_width": 0.30992,
        "across_front_width": 0.36054, "shoulder_width": 0.38434, "shoulder_length": 0.10115, "arm_length": 0.52447,
        "waist_to_hip_length": 0.24658, "crotch_length": 0.79675, "inside_leg": 0.76934,
    },
    "male": {
        "stature": 1.78, "neck_girth": 0.36749, "chest_girth": 1.01958, "underbust_girth": 0.96228,
        "waist_girth": 0.89471, "omphalion_waist_girth": 0.90568, "hip_girth": 1.01655, "thigh_girth": 0.6032,
        "upper_arm_girth": 0.33993, "armscye_girth": 0.52947, "knee_girth": 0.38161, "calf_girth": 0.3882,
        "ankle_girth": 0.23237, "wrist_girth": 0.17622, "back_waist_length": 0.44618, "across_back_width": 0.36483,
        "across_front_width": 0.38864, "shoulder_width": 0.44797, "shoulder_length": 0.12396, "arm_length": 0.60256,
        "waist_to_hip_length": 0.21698, "crotch_length": 0.723, "inside_leg": 0.85528,
    },
}
# The default trunk model (P2 at 40 mm, rigid bone, free cuts, shipped materials): first frequencies, Hz.
TRUNK_FREQUENCIES = {
    "female": [1.6892, 2.7428, 2.7981, 2.865, 3.213, 3.4286, 3.7099, 3.7799],
    "male": [1.6006, 2.3667, 2.6012, 2.667, 3.069, 3.1184, 3.3818, 3.5628],
}


@pytest.mark.parametrize("sex", ["female", "male"])
def test_default_body_measurements(request, sex: str) -> None:
    values = measure(request.getfixturevalue(sex)).as_dict()
    assert values == pytest.approx(MEASUREMENTS[sex], abs=5e-5)  # 0.05 mm: rounding of the pinned figures


@pytest.mark.slow
@pytest.mark.parametrize("sex", ["female", "male"])
def test_default_trunk_first_frequencies(sex: str) -> None:
    model = build_elastic_model(default_body(sex))
    assert list(model.modes.frequencies[:8]) == pytest.approx(TRUNK_FREQUENCIES[sex], rel=2e-4)
