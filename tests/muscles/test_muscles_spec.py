"""The muscle list: the default set, its coverage of every DOF, and broken lists."""

from pathlib import Path

import numpy as np
import pytest

from hitogata.errors import HitogataError
from hitogata.muscles.geometry import place_muscles
from hitogata.muscles.spec import default_muscles_path, load_muscle_spec
from hitogata.skeleton.placement import place_skeleton
from hitogata.skeleton.spec import load_skeleton_spec

SKELETON = load_skeleton_spec()
DEFAULT = default_muscles_path().read_text()
REQUIRED = [
    "rectus_abdominis", "erector_spinae", "external_oblique", "sternocleidomastoid", "deltoid",
    "pectoralis_major", "latissimus_dorsi", "biceps_brachii", "triceps_brachii", "pronator_teres", "supinator",
    "iliopsoas", "gluteus_maximus", "quadriceps", "hamstrings", "gastrocnemius", "tibialis_anterior",
]  # fmt: skip


@pytest.fixture(scope="module", params=["female", "male"])
def muscles(request):
    body = request.getfixturevalue(request.param)
    return place_muscles(load_muscle_spec(SKELETON), place_skeleton(SKELETON, body.rig))


def test_default_set_has_the_named_muscles_left_and_right():
    spec = load_muscle_spec(SKELETON)
    names = set(spec.names)
    assert len(names) >= 40
    for muscle in REQUIRED:
        assert {f"{muscle}_l", f"{muscle}_r"} <= names, muscle
    kinds = {m.name: m.kind for m in spec.muscles}
    assert kinds["pronator_teres_l"] == kinds["supinator_r"] == "rotation"
    assert kinds["biceps_brachii_l"] == "flexion"
    by_name = {m.name: m for m in spec.muscles}
    for m in spec.muscles:
        assert by_name[m.antagonist].antagonist == m.name  # antagonists come in pairs


def test_default_set_moves_every_dof_both_ways(muscles):
    sk = muscles.skeleton
    ways: dict[int, set[int]] = {d: set() for d in range(sk.n_dofs)}
    for m in range(len(muscles.names)):
        for d in muscles.dofs(m):
            ways[d].add(int(muscles.sense[m]))
    missing = [sk.dof_names[d] for d, senses in ways.items() if senses != {-1, 1}]
    assert not missing


def test_every_muscle_spans_its_joints_whole_range_of_motion(muscles):
    """Eq. 1 stays defined (0 ≤ θ ≤ π, eq. 2: φ ≥ 0) over the joints' whole clinical ranges."""
    margin = np.radians(3.0)
    short = [
        n
        for k, n in enumerate(muscles.names)
        if muscles.reach_low[k] > muscles.low[k] - margin or muscles.reach_high[k] < muscles.high[k] + margin
    ]
    assert not short


def test_attachments_sit_where_the_list_says(muscles):
    sk = muscles.skeleton
    for k, m in enumerate(muscles.spec.muscles):
        assert np.allclose(muscles.origins[k], sk.point(sk.index(m.origin.part), m.origin.at))
        assert np.allclose(muscles.insertions[k], sk.point(sk.index(m.insertion.part), m.insertion.at))
    biceps = muscles.index("biceps_brachii_l")
    assert np.allclose(muscles.centres[biceps], sk.joints[sk.index("forearm_l")])
    assert muscles.axes[biceps] @ sk.dof_axes[sk.dof_index("forearm_l.flexion")] == pytest.approx(1.0)


def test_trunk_muscles_share_their_angle_among_the_vertebrae(muscles):
    sk = muscles.skeleton
    ra = muscles.index("rectus_abdominis_l")
    dofs = muscles.dofs(ra)
    assert len(dofs) == 17 and all(sk.dof_names[d].endswith(".flexion") for d in dofs)
    assert muscles.share_pos[ra, dofs].sum() == pytest.approx(1.0)
    assert muscles.high[ra] == pytest.approx(np.radians(80.0), abs=np.radians(0.5))  # AAOS thoracolumbar flexion
    fingers = muscles.index("flexor_digitorum_superficialis_r")
    assert np.all(muscles.share_pos[fingers, muscles.dofs(fingers)] == 1.0)  # four fingers alike


def test_left_and_right_muscles_mirror_each_other(muscles):
    for k, name in enumerate(muscles.names):
        if name.endswith("_l"):
            twin = muscles.index(name[:-1] + "r")
            # the male rig's neck03 head sits 3 mm off the midline, which tilts the neck's helices a little
            tolerance = 5e-2 if muscles.rotation[k] else 1e-2
            assert muscles.rest_length[k] == pytest.approx(muscles.rest_length[twin], rel=tolerance), name
            opposed = muscles.spec.muscles[k].antagonist == muscles.names[twin]  # e.g. the two obliques
            assert (muscles.sense[k] == -muscles.sense[twin]) == opposed, name


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "muscles.toml"
    path.write_text(text)
    return path


BICEPS = 'name = "biceps_brachii_l"\nkind = "flexion"\njoints = ["forearm_l"]\ndof = "flexion"\n'


@pytest.mark.parametrize(
    "old, new, message",
    [
        ('name = "biceps_brachii_l"\n', 'name = "triceps_brachii_l"\n', "duplicate name"),
        (
            'joints = ["forearm_l"]\ndof = "flexion"\norigin = { part = "upper_arm_l"',
            'joints = ["forearm_l"]\ndof = "curl"\norigin = { part = "upper_arm_l"',
            "no degree of freedom 'curl'",
        ),
        (
            'antagonist = "triceps_brachii_l"',
            'antagonist = "triceps_l"',
            "antagonist 'triceps_l' is not another muscle",
        ),
        ('antagonist = "triceps_brachii_l"', 'antagonist = "deltoid_l"', "antagonist 'deltoid_l' moves abduction"),
        (BICEPS, BICEPS.replace('"flexion"\njoints', '"twist"\njoints'), "unknown kind 'twist'"),
        (BICEPS, BICEPS.replace('"forearm_l"', '"forearm_x"'), "unknown part 'forearm_x'"),
        (BICEPS, BICEPS + "radius = 0.02\n", "apply to rotation muscles only"),
        (BICEPS, BICEPS.replace('"forearm_l"', '"upper_arm_l"'), "is moved by joint 'upper_arm_l'"),
        (BICEPS, BICEPS + "strength = 3\n", "unknown key 'strength'"),
    ],
    ids=["duplicate", "dof", "antagonist", "antagonist-dof", "kind", "part", "radius", "proximal", "key"],
)
def test_broken_muscle_lists_give_one_line_errors(tmp_path, old, new, message):
    text = DEFAULT.replace(old, new, 1)
    assert text != DEFAULT
    path = write(tmp_path, text)
    with pytest.raises(HitogataError) as err:
        load_muscle_spec(SKELETON, path)
    assert message in str(err.value) and str(path) in str(err.value) and "\n" not in str(err.value)


def test_geometry_mistakes_are_caught_when_placed(tmp_path, female):
    sk = place_skeleton(SKELETON, female.rig)
    start = DEFAULT.index('name = "biceps_brachii_l"')
    origin = DEFAULT.index("origin = ", start)
    line_end = DEFAULT.index("\n", origin)
    text = DEFAULT[:origin] + 'origin = { part = "upper_arm_l", at = [0, 1, 0] }' + DEFAULT[line_end:]
    with pytest.raises(HitogataError, match="biceps_brachii_l.*on the joint's axis|biceps_brachii_l.*no lever"):
        place_muscles(load_muscle_spec(SKELETON, write(tmp_path, text)), sk)
