"""The body from real units: targets met, a clean surface, joints inside, knees mended."""

import numpy as np
import pytest

from hitogata.body.assets import load_assets
from hitogata.body.model import STATURE_RANGE, Body
from hitogata.errors import HitogataError
from hitogata.geometry.mesh_checks import (
    connected_component_count,
    genus,
    is_closed,
    is_consistently_oriented,
    self_intersections,
    winding_number,
)
from hitogata.body.shape import ShapeParameters

# Bones whose skin is allowed to touch itself in MakeHuman shapes (docs/body.md):
# the toes and the face (eye corners, mouth corners).
EXEMPT_PREFIXES = ("toe", "foot", "head", "oris", "levator", "oculi", "orbicularis", "jaw", "eye",
                   "risorius", "temporalis", "special", "tongue")
# Face bones end on the skin by MakeHuman's design (VERTEX placement): not joints of the body.
# The little toes' joint cubes of short bodies touch the skin (docs/body.md): toes are left out.
NOT_BODY_JOINTS = ("oris", "levator", "oculi", "orbicularis", "jaw", "eye", "risorius", "temporalis",
                   "special", "tongue", "toe")

# Grid of the acceptance: both sexes, 150–195 cm, BMI 18–35 (women to 33, the data's top: docs/body.md).
GRID = [
    (sex, stature, bmi)
    for sex, bmis in (("female", (18.0, 22.0, 26.0, 30.0, 33.0)), ("male", (18.0, 22.0, 26.0, 30.0, 35.0)))
    for stature in (1.50, 1.65, 1.80, 1.95)
    for bmi in bmis
]


def _trunk_and_limb_faces() -> np.ndarray:
    """Faces none of whose corners is mainly moved by a toe, foot or face bone."""
    a = load_assets()
    dominant = np.asarray(a.skin_weights.argmax(axis=1)).ravel()
    exempt = np.array([n.startswith(EXEMPT_PREFIXES) for n in a.bone_names])
    return ~exempt[dominant[a.triangles]].any(axis=1)


@pytest.mark.parametrize("sex,stature,bmi", GRID)
def test_targets_met_and_surface_clean(sex: str, stature: float, bmi: float) -> None:
    mass = bmi * stature**2
    body = Body.from_measurements(sex, 30.0, stature, mass)
    assert abs(body.stature - stature) < 0.002
    assert abs(body.mass - mass) / mass < 0.02
    assert is_closed(body.faces) and is_consistently_oriented(body.faces)
    assert connected_component_count(body.faces) == 1 and genus(body.faces) == 0
    assert body.volume > 0  # outward normals
    pairs = self_intersections(body.vertices, body.faces)
    keep = _trunk_and_limb_faces()
    assert not np.any(keep[pairs[:, 0]] & keep[pairs[:, 1]]), "trunk or limb skin passes through itself"


def test_frame_stands_on_floor_between_ankles(female: Body) -> None:
    assert female.vertices[:, 1].min() == pytest.approx(0.0, abs=1e-12)
    ankles = female.rig.heads[[female.rig.index("foot.L"), female.rig.index("foot.R")]]
    assert np.allclose(ankles[:, [0, 2]].mean(axis=0), 0.0, atol=1e-12)
    assert ankles[0, 0] > 0  # +X is the body's left
    nose_z = female.vertices[female.vertices[:, 1] > 0.9 * female.stature][:, 2].max()
    assert nose_z > 0.05  # the face looks towards +Z


@pytest.mark.parametrize("sex", ["female", "male"])
@pytest.mark.parametrize("stature", STATURE_RANGE)
def test_joint_centres_inside_body(sex: str, stature: float) -> None:
    body = Body.from_measurements(sex, 30.0, stature, 22.5 * stature**2)
    joints = [i for i, n in enumerate(body.rig.names) if not n.startswith(NOT_BODY_JOINTS)]
    winding = winding_number(body.vertices, body.faces, body.rig.heads[joints])
    outside = [body.rig.names[joints[i]] for i in np.flatnonzero(winding < 0.5)]
    assert not outside, f"joints outside the skin: {outside}"


@pytest.mark.parametrize("height", [0.0, 1.0])
def test_knee_mended_at_extreme_heights(height: float) -> None:
    """MPFB2's height targets move the knee cube 5–7 cm; the regressed knee stays in its ring."""
    a = load_assets()
    body = Body.from_parameters(ShapeParameters(sex=0.0, height=height))
    k = body.rig.index("lowerleg01.L")
    cube_knee = (a.joint_regressor @ body.all_vertices)[k]
    knee = body.rig.heads[k]
    assert np.linalg.norm(cube_knee - knee) > 0.05  # the defect is real and is avoided
    skin = body.vertices
    ring = skin[(np.abs(skin[:, 1] - knee[1]) < 0.02) & (np.hypot(*(skin[:, [0, 2]] - knee[[0, 2]]).T) < 0.1)]
    assert np.linalg.norm(ring.mean(axis=0)[[0, 2]] - knee[[0, 2]]) < 0.02  # centred in the leg
    # Knee height ≈ 0.285 × stature (Drillis & Contini 1966); short MakeHuman bodies have shorter legs.
    assert 0.25 < knee[1] / body.stature < 0.31
    assert np.allclose(body.rig.tails[body.rig.index("upperleg02.L")], knee)


def test_skin_weights_rows_sum_to_one(female: Body) -> None:
    w = female.skin_weights
    assert w.shape == (len(female.vertices), len(female.rig.names))
    assert np.allclose(np.asarray(w.sum(axis=1)).ravel(), 1.0, atol=1e-9)
    assert w.min() >= 0


def test_default_bodies(female: Body, male: Body) -> None:
    assert female.stature == pytest.approx(1.65, abs=2e-3) and female.mass == pytest.approx(62.0, rel=0.02)
    assert male.stature == pytest.approx(1.78, abs=2e-3) and male.mass == pytest.approx(78.0, rel=0.02)
    assert male.bmi == pytest.approx(male.mass / male.stature**2)


def test_same_inputs_same_arrays() -> None:
    a = Body.from_measurements("female", 40.0, 1.70, 60.0)
    b = Body.from_measurements("female", 40.0, 1.70, 60.0)
    assert a.vertices.tobytes() == b.vertices.tobytes()
    assert a.rig.heads.tobytes() == b.rig.heads.tobytes()


@pytest.mark.parametrize(
    "kwargs,message",
    [
        (dict(stature=3.0, mass=60.0), "stature 300.0 cm: allowed 140–210 cm"),
        (dict(stature=1.65, mass=-1.0), "mass -1.0 kg: allowed a finite positive number"),
        (dict(stature=float("nan"), mass=60.0), "stature nan m: allowed a finite positive number"),
        (dict(stature=1.65, mass=150.0), "mass 150.0 kg at stature 165.0 cm: BMI 55.1, allowed up to 50 (136.1 kg)"),
        (dict(stature=1.65, mass=30.0), "mass 30.0 kg at stature 165.0 cm: allowed 34.1–"),
        (dict(stature=1.65, mass=100.0, muscle=0.5), "mass 100.0 kg at stature 165.0 cm: allowed 44.6–59.6 kg (BMI 16.4–21.9)"),
        (dict(stature=1.65, mass=60.0, muscle=1.5), "shape parameter muscle=1.5: allowed 0..1"),
        (dict(sex="alien", stature=1.65, mass=60.0), "sex 'alien': allowed 'female', 'male'"),
        (dict(age=0.5, stature=0.7, mass=8.0), "age 0.5 years: allowed 1..90"),
    ],
)
def test_bad_measurements_one_line_error(kwargs: dict, message: str) -> None:
    args = dict(sex="female", age=30.0) | kwargs
    with pytest.raises(HitogataError) as err:
        Body.from_measurements(**args)
    assert message in str(err.value) and "\n" not in str(err.value)


def test_stature_range_is_the_documented_one() -> None:
    assert STATURE_RANGE == (1.40, 2.10)
    lo = Body.from_measurements("female", 30.0, 1.40, 40.0)
    assert lo.stature == pytest.approx(1.40, abs=2e-3)


def test_age_changes_shape_past_25_only() -> None:
    young = Body.from_parameters(ShapeParameters(age=20.0))
    at25 = Body.from_parameters(ShapeParameters(age=25.0))
    old = Body.from_parameters(ShapeParameters(age=80.0))
    assert np.array_equal(young.vertices, at25.vertices)  # documented: adult data starts at 25
    assert np.abs(old.vertices - at25.vertices).max() > 0.01
