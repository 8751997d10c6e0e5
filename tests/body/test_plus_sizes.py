"""Adults to BMI 50: MakeHuman's weight targets extrapolated past their slider (`shape.WEIGHT_MAX`), the
BMI cap, and the shipped example study's bodies all within reach (docs/howto/children-and-plus-sizes.md)."""

from __future__ import annotations

from importlib import resources

import numpy as np
import pytest

from hitogata.body.model import ADULT_BMI_MAX, Body, mass_range
from hitogata.errors import HitogataError
from hitogata.geometry import self_intersections
from hitogata.geometry.mesh_checks import enclosed_volume, is_closed, is_consistently_oriented
from hitogata.measure import measure
from hitogata.body.rest_contact import contact_groups
from hitogata.study.spec import load_study

pytestmark = pytest.mark.slow  # whole-body meshes

GIRTHS = ("waist_girth", "hip_girth", "thigh_girth", "upper_arm_girth", "chest_girth")


def test_the_example_study_refuses_none_of_its_bodies():
    """Every sampled body lies inside the build path's mass range at its stature and under the BMI cap,
    checked at each sex's shortest, median and tallest sampled stature (the range's BMI ends change
    by under 1.5 over 150–195 cm: docs/body.md), without building the bodies."""
    spec = load_study(resources.files("hitogata").joinpath("data", "studies", "example.toml"))
    assert len(spec.bodies) >= 200
    for sex in ("female", "male"):
        bodies = [b for b in spec.bodies if b.sex == sex]
        stature = np.array([b.stature for b in bodies])
        bmi = np.array([b.mass for b in bodies]) / stature**2
        assert stature.min() >= 1.40 and stature.max() <= 2.10
        ends = [mass_range(sex, 30.0, float(s)) for s in (stature.min(), np.median(stature), stature.max())]
        lightest = max(lo / s**2 for (lo, _), s in zip(ends, (stature.min(), np.median(stature), stature.max())))
        heaviest = min(hi / s**2 for (_, hi), s in zip(ends, (stature.min(), np.median(stature), stature.max())))
        assert heaviest > ADULT_BMI_MAX  # the cap, not the shape, ends the range
        # ANSUR II: women BMI 17.7–32.8 here, men 16.9–36.6; the path reaches from BMI 13.2 / 15.0
        assert lightest + 1.0 < bmi.min() and bmi.max() <= ADULT_BMI_MAX, (sex, lightest, bmi.min(), bmi.max())


def test_beyond_bmi_50_is_refused_in_one_line():
    with pytest.raises(HitogataError) as error:
        Body.from_measurements("male", stature=1.80, mass=170.0)
    assert str(error.value) == "mass 170.0 kg at stature 180.0 cm: BMI 52.5, allowed up to 50 (162.0 kg) for adults"


def _crossing_faces(body: Body) -> set[tuple[int, int]]:
    return set(map(tuple, np.sort(self_intersections(body.vertices, body.faces), axis=1).tolist()))


def _new_crossings_off_hands_and_feet(body: Body) -> list[tuple[int, int]]:
    """The body's crossing face pairs that MakeHuman's heaviest body of its shape (weight 1) has not, less
    those within one hand, foot or head (`rest_contact.RIGID`): the base mesh's fingers and toes touch and
    cross in MakeHuman's own bodies, and a fifth of a millimetre moves which of their pairs cross (18 → 30
    at the fingers of a man of 155 cm at BMI 42)."""
    heaviest = Body.from_parameters(body.params.with_(weight=min(body.params.weight, 1.0)))
    groups, folding = contact_groups(heaviest.rig, body.skin_weights)
    face_group = groups[body.faces[:, 0]]
    return [(i, j) for i, j in _crossing_faces(body) - _crossing_faces(heaviest)
            if not (face_group[i] == face_group[j] and face_group[i] not in folding)]


@pytest.mark.parametrize("sex", ["female", "male"])
def test_plus_size_bodies_build_close_and_measure(sex):
    """BMI 35, 42 and 50 at 155 and 190 cm: stature and mass met, closed and outward, measured; the skin
    crosses itself nowhere but where MakeHuman's heaviest body of the same stature does (the base mesh's
    own pairs at the eyes, toes and fingers: 0–35): where heavy skin meets skin it touches. Without the
    rest contact the extrapolated skin crossed itself at 116–228 pairs at BMI 50."""
    for stature in (1.55, 1.90):
        rows = []
        for bmi in (35.0, 42.0, 50.0):
            body = Body.from_measurements(sex, 30.0, stature, bmi * stature**2)
            assert body.stature == pytest.approx(stature, abs=1e-3) and body.bmi == pytest.approx(bmi, rel=1e-3)
            assert is_closed(body.faces) and is_consistently_oriented(body.faces)
            assert enclosed_volume(body.vertices, body.faces) > 0
            girths = measure(body).as_dict()
            rows.append([girths[name] for name in GIRTHS])
            # one thigh: here 0.56–0.63 of the hip girth at BMI 50 (both thighs together would be over 1)
            assert girths["thigh_girth"] < 0.7 * girths["hip_girth"], girths
            assert not _new_crossings_off_hands_and_feet(body), (stature, bmi)
        assert np.all(np.diff(rows, axis=0) > 0.005), rows  # every girth grows with BMI


def test_contact_groups_part_the_limbs_and_the_trunk():
    """The rig's limbs, each side apart, and the trunk; hands, feet and head do not fold onto themselves."""
    body = Body.from_measurements("female")
    groups, folding = contact_groups(body.rig, body.skin_weights)
    assert groups.shape == (len(body.vertices),) and groups.max() + 1 == 1 + 2 * 7 + 2  # trunk, 7 limbs a side, neck, head
    assert len(folding) == groups.max() + 1 - 5
    x = body.vertices[:, 0]
    for g in range(groups.max() + 1):  # a limb's skin lies on its own side; the trunk, neck and head across the middle
        side = np.sign(np.median(x[groups == g]))
        assert np.mean(np.sign(x[groups == g]) == side) > 0.99 or abs(np.median(x[groups == g])) < 0.01
