"""The skeleton on a body: joint centres, frames, axes, and the 163 → 65 skinning weights."""

import numpy as np
import pytest

from hitogata.body import Body
from hitogata.skeleton.placement import place_skeleton
from hitogata.skeleton.spec import load_skeleton_spec
from hitogata.skeleton.weights import part_weights

SPEC = load_skeleton_spec()
AXIAL = (
    ["pelvis"]
    + [f"lumbar_{k}" for k in range(5, 0, -1)]
    + [f"thoracic_{k}" for k in range(12, 0, -1)]
    + [f"cervical_{k}" for k in range(7, 0, -1)]
    + ["head"]
)


@pytest.fixture(scope="module", params=["female", "male"])
def body(request) -> Body:
    return request.getfixturevalue(request.param)


@pytest.fixture(scope="module")
def skeleton(body):
    return place_skeleton(SPEC, body.rig)


def test_all_65_joint_centres_and_frames(skeleton, body):
    assert skeleton.joints.shape == (65, 3) and skeleton.frames.shape == (65, 3, 3)
    frames = skeleton.frames
    assert np.allclose(frames @ frames.transpose(0, 2, 1), np.eye(3), atol=1e-12)
    assert np.allclose(np.linalg.det(frames), 1.0)
    assert np.all(skeleton.lengths > 0.005)
    rig = body.rig
    assert np.allclose(skeleton.joints[skeleton.index("forearm_l")], rig.heads[rig.index("lowerarm01.L")])
    assert np.allclose(skeleton.joints[skeleton.index("thigh_r")], rig.heads[rig.index("upperleg01.R")])


def test_vertebrae_climb_the_spine_in_documented_proportions(skeleton, body):
    axial = np.array([skeleton.index(n) for n in AXIAL])
    heights = skeleton.joints[axial, 1]
    assert np.all(np.diff(heights[1:]) > 0)  # L5/S1 up to C0/C1
    hips = skeleton.joints[[skeleton.index("thigh_l"), skeleton.index("thigh_r")], 1].mean()
    l5s1, t12l1, c7t1 = (skeleton.joints[skeleton.index(n), 1] for n in ("lumbar_5", "thoracic_12", "cervical_7"))
    assert 0.04 < l5s1 - hips < 0.15  # the lumbosacral joint sits above the hip joints
    lumbar, thoracic = t12l1 - l5s1, c7t1 - t12l1
    assert 0.45 < lumbar / thoracic < 0.85  # Gray's: lumbar 18 cm, thoracic 28 cm (0.64), along a curve
    assert abs(skeleton.joints[axial, 0]).max() < 0.005  # on the midline


def test_frames_point_along_the_bone_and_to_the_front(skeleton):
    i = skeleton.index("upper_arm_l")
    y = skeleton.frames[i][:, 1]
    assert np.allclose(y, (skeleton.tails[i] - skeleton.joints[i]) / skeleton.lengths[i])
    assert skeleton.frames[i][2, 2] > 0.9  # z: the front
    assert np.allclose(skeleton.frames[skeleton.index("pelvis")], np.eye(3))


def test_rest_angles_match_the_body(skeleton):
    """The TOML's rest angles are measured: check them on each default body."""

    def angle(u, v):
        return np.degrees(np.arccos(u @ v / np.linalg.norm(u) / np.linalg.norm(v)))

    j = lambda n: skeleton.joints[skeleton.index(n)]  # noqa: E731
    upper, fore = j("forearm_l") - j("upper_arm_l"), j("hand_l") - j("forearm_l")
    rest = dict(zip(skeleton.dof_names, np.degrees(skeleton.rest)))
    assert angle(upper, fore) == pytest.approx(rest["forearm_l.flexion"], abs=1e-9)  # measured
    assert 35 < rest["forearm_l.flexion"] < 50
    assert np.degrees(np.arctan2(upper[0], -upper[1])) == pytest.approx(rest["upper_arm_l.abduction"], abs=4)
    thigh, shank = j("shank_l") - j("thigh_l"), j("foot_l") - j("shank_l")
    assert angle(thigh, shank) == pytest.approx(rest["shank_l.flexion"], abs=4)


def test_axes_are_mirror_images_left_and_right(skeleton):
    mirror_pseudo = np.array([1.0, -1.0, -1.0])  # mirroring x flips an axis' y and z
    for name in skeleton.dof_names:
        if name.split(".")[0].endswith("_l"):
            left = skeleton.dof_axes[skeleton.dof_index(name)]
            right = skeleton.dof_axes[skeleton.dof_index(name.replace("_l.", "_r."))]
            assert left * mirror_pseudo @ right > 0.98, name


def test_weights_cover_every_vertex_with_rows_summing_to_one(skeleton, body):
    w = part_weights(skeleton, body.rig, body.skin_weights, body.vertices)
    assert w.shape == (len(body.vertices), 65)
    assert np.allclose(np.asarray(w.sum(axis=1)).ravel(), 1.0, atol=1e-12)
    assert w.data.min() > 0 and np.diff(w.indptr).min() >= 1
    per_part = np.asarray(w.sum(axis=0)).ravel()
    assert np.all(per_part > 1.0)  # every part moves some skin, every vertebra included
    rig_mass = np.asarray(body.skin_weights.sum(axis=0)).ravel()
    head_bones = [body.rig.index(n) for n in body.rig.names if n.startswith(("levator", "oris", "temporalis", "eye"))]
    assert w[:, skeleton.index("head")].sum() > rig_mass[head_bones].sum()  # face bones merged into the head


def test_spine_weights_follow_the_height_of_the_skin(skeleton, body):
    w = part_weights(skeleton, body.rig, body.skin_weights, body.vertices)
    axial = [skeleton.index(n) for n in AXIAL]
    mean_height = (w.T @ body.vertices[:, 1])[axial] / np.asarray(w.sum(axis=0)).ravel()[axial]
    assert np.all(np.diff(mean_height) > 0)
