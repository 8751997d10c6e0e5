"""The skeleton list: the shipped one, each kind of broken list, and adding a part."""

from pathlib import Path

import numpy as np
import pytest

from hitogata.errors import HitogataError
from hitogata.posing import Poser
from hitogata.skeleton.spec import default_skeleton_path, load_skeleton_spec

DEFAULT = default_skeleton_path().read_text()


def write(tmp_path: Path, text: str, name: str = "skeleton.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def edited(old: str, new: str, text: str = DEFAULT) -> str:
    assert text.count(old) == 1, old
    return text.replace(old, new)


def test_default_list_has_65_parts_rooted_at_the_pelvis():
    spec = load_skeleton_spec()
    assert len(spec.parts) == 65
    assert spec.parts[0].name == "pelvis" and spec.parts[0].parent is None
    assert sum(p.parent is None for p in spec.parts) == 1
    names = spec.names
    for region in ("lumbar_", "thoracic_", "cervical_"):
        assert sum(n.startswith(region) for n in names) == {"lumbar_": 5, "thoracic_": 12, "cervical_": 7}[region]
    for part in ("head", "upper_arm_l", "forearm_r", "hand_l", "thigh_r", "shank_l", "foot_r"):
        assert part in names
    parents = spec.parents
    assert all(parents[i] < i for i in range(1, len(parents)))  # parents before children


def test_degrees_are_converted_once_to_radians():
    spec = load_skeleton_spec()
    elbow = next(d for d in spec.parts[spec.index("forearm_l")].dofs if d.name == "flexion")
    assert elbow.upper == pytest.approx(np.radians(150)) and elbow.lower == 0.0
    assert elbow.rest is None  # "measured": the bend of the elbow on each body
    shoulder = next(d for d in spec.parts[spec.index("upper_arm_l")].dofs if d.name == "abduction")
    assert shoulder.rest == pytest.approx(np.radians(42))


@pytest.mark.parametrize(
    "old, new, message",
    [
        ('name = "pelvis"\n', 'name = "pelvis"\nparent = "lumbar_5"\n', "no root part"),
        ('name = "thigh_l"\nparent = "pelvis"\n', 'name = "thigh_l"\n', "two roots"),
        ('name = "lumbar_5"\nparent = "pelvis"\n', 'name = "lumbar_5"\nparent = "lumbar_3"\n', "form a cycle"),
        ('name = "jaw"\nparent = "head"\n', 'name = "jaw"\nparent = "skull"\n', "unknown parent 'skull'"),
        ('name = "jaw"\n', 'name = "head"\n', "duplicate name"),
        (
            '{ name = "flexion", axis = "x", min = 0, max = 135, rest = 9 },',
            '{ name = "flexion", axis = "x", min = 135, max = 0, rest = 9 },',
            "min 135 >= max 0",
        ),
        (
            '{ name = "depression", axis = "x", min = 0, max = 30 },',
            '{ name = "depression", axis = "w", min = 0, max = 30 },',
            "unknown axis 'w'",
        ),
    ],
    ids=["no-root", "two-roots", "cycle", "unknown-parent", "duplicate", "min-ge-max", "unknown-axis"],
)
def test_each_broken_list_gives_its_own_one_line_error(tmp_path, old, new, message):
    text = DEFAULT.replace(old, new, 1)  # the knee's line appears twice (left, right): the first is enough
    assert text != DEFAULT
    path = write(tmp_path, text)
    with pytest.raises(HitogataError) as err:
        load_skeleton_spec(path)
    text = str(err.value)
    assert message in text and str(path) in text and "\n" not in text


@pytest.mark.parametrize(
    "old, new, message",
    [
        ('name = "jaw"\n', 'name = "jaw"\ncolour = "red"\n', "unknown key 'colour'"),
        ('name = "jaw"\n', 'name = "jaw"\nframe = "diagonal"\n', "frame = 'diagonal'"),
        ('tail = { part = "thoracic_1" }\n', "", "has 3 children, so it needs a 'tail'"),
        (
            '{ name = "depression", axis = "x", min = 0, max = 30 },',
            '{ name = "depression", axis = "x", min = 0, max = 30, rest = 40 },',
            "rest 40 outside",
        ),
        ('bones = ["jaw"]', 'bones = ["jaw", "head"]', "bone 'head' already given"),
        ('joint = { bone = "jaw" }', 'joint = { between = ["jaw"], at = 2.0 }', "allowed two bones and 0 <= at <= 1"),
        ('name = "jaw"\n', "name = 3\n", "expected a string"),
        (
            '{ name = "depression", axis = "x", min = 0, max = 30 },',
            '{ name = "depression", axis = "x", min = 0, max = 30, rest = "measured" },',
            "needs a hinge axis",
        ),
    ],
    ids=["unknown-key", "frame", "missing-tail", "rest", "bone-twice", "between", "type", "measured"],
)
def test_other_mistakes_are_named_too(tmp_path, old, new, message):
    path = write(tmp_path, edited(old, new))
    with pytest.raises(HitogataError, match=message):
        load_skeleton_spec(path)


def test_unreadable_files_are_one_line_errors(tmp_path):
    with pytest.raises(HitogataError, match="no such file"):
        load_skeleton_spec(tmp_path / "missing.toml")
    with pytest.raises(HitogataError, match="not valid TOML"):
        load_skeleton_spec(write(tmp_path, "[[part]\nname ="))


def test_unknown_rig_bones_are_caught_when_placed_on_a_body(tmp_path, female):
    path = write(tmp_path, edited('joint = { bone = "jaw" }', 'joint = { bone = "mandible" }'))
    with pytest.raises(HitogataError, match="unknown rig bone 'mandible'"):
        Poser.from_body(female, skeleton=path)


HALLUX = """
[[part]]
name = "hallux_l"
parent = "foot_l"
joint = { bone = "toe1-1.L" }
tail = { bone = "toe1-2.L", at = "tail" }
frame = "world"
bones = ["toe1-1.L", "toe1-2.L"]
dof = [{ name = "flexion", axis = "x", min = -70, max = 45 }]
"""

HALLUX_MUSCLES = """
[[muscle]]
name = "flexor_hallucis_longus_l"
kind = "flexion"
joints = ["hallux_l"]
dof = "flexion"
origin = { part = "foot_l", at = [0, -0.4, 0.5] }
insertion = { part = "hallux_l", at = [0, -0.3, 0.8] }
antagonist = "extensor_hallucis_longus_l"

[[muscle]]
name = "extensor_hallucis_longus_l"
kind = "flexion"
joints = ["hallux_l"]
dof = "flexion"
origin = { part = "foot_l", at = [0, 0.2, 0.5] }
insertion = { part = "hallux_l", at = [0, 0.3, 0.8] }
antagonist = "flexor_hallucis_longus_l"
"""


def test_adding_a_part_to_a_copy_works_end_to_end(tmp_path, female):
    text = edited('\nbones = ["toe1-1.L", "toe2-1.L",', '\nbones = ["toe2-1.L",') + HALLUX
    skeleton = write(tmp_path, text)
    muscles_text = Path(str(default_skeleton_path()).replace("skeleton.toml", "muscles.toml")).read_text()
    muscles = write(tmp_path, muscles_text + HALLUX_MUSCLES, "muscles.toml")
    poser = Poser.from_body(female, skeleton=skeleton, muscles=muscles)

    sk = poser.skeleton
    assert len(sk.names) == 66 and sk.names[sk.parents[sk.index("hallux_l")]] == "foot_l"
    hallux = sk.index("hallux_l")
    weights = poser.skin.weights
    assert weights.shape == (len(female.vertices), 66)
    assert weights[:, hallux].sum() > 1.0  # the great toe's skin now follows the new part
    assert np.allclose(np.asarray(weights.sum(axis=1)).ravel(), 1.0)

    posed = poser.pose(contractions={"flexor_hallucis_longus_l": 0.05})
    flexion = posed.angle("hallux_l.flexion")
    assert flexion > 0.0
    moved = np.linalg.norm(posed.vertices - female.vertices, axis=1)
    toe = np.asarray(weights[:, hallux].todense()).ravel() > 0.99
    assert moved[toe].min() > 0.0 and np.all(moved[np.asarray(weights[:, sk.index("head")].todense()).ravel() > 0] == 0)
    lengths = dict(zip(posed.muscle_names, posed.muscle_lengths))
    rest = dict(zip(poser.muscles.names, poser.muscles.rest_length))
    assert lengths["extensor_hallucis_longus_l"] > rest["extensor_hallucis_longus_l"]  # the antagonist follows
