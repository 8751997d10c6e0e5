"""Forward kinematics: bone lengths kept, the zero pose exact, an elbow at 90°, limits, batches."""

import numpy as np
import pytest

from hitogata.errors import HitogataError
from hitogata.posing import Poser
from hitogata.skeleton.kinematics import Kinematics, forward_kinematics, limit_violations
from hitogata.geometry.rotations import axis_rotations


@pytest.fixture(scope="module")
def poser(female) -> Poser:
    return Poser.from_body(female)


@pytest.fixture(scope="module")
def random_angles(poser) -> np.ndarray:
    sk = poser.skeleton
    return np.random.default_rng(7).uniform(sk.lower, sk.upper, (200, sk.n_dofs))


def test_bone_lengths_are_kept_over_random_poses_within_limits(poser, random_angles):
    sk = poser.skeleton
    pose = poser.kinematics.pose(random_angles, limits="raise")
    child = np.arange(1, len(sk.names))
    rest = np.linalg.norm(sk.joints[child] - sk.joints[sk.parents[child]], axis=1)
    posed = np.linalg.norm(pose.joints[:, child] - pose.joints[:, sk.parents[child]], axis=2)
    assert np.abs(posed - rest).max() < 1e-12
    rest_tails = np.linalg.norm(sk.tails - sk.joints, axis=1)
    assert np.abs(np.linalg.norm(pose.tails - pose.joints, axis=2) - rest_tails).max() < 1e-12
    r = pose.rotations
    assert np.abs(r @ r.transpose(0, 1, 3, 2) - np.eye(3)).max() < 1e-12
    assert np.abs(np.linalg.det(r) - 1.0).max() < 1e-12


def test_each_joint_centre_rides_on_its_parent(poser, random_angles):
    """A part's joint centre moves with its parent: M_parent(J) = M_child(J)."""
    sk = poser.skeleton
    pose = poser.kinematics.pose(random_angles[:20])
    on_parent = (
        np.einsum("pnij,nj->pni", pose.rotations[:, sk.parents[1:]], sk.joints[1:])
        + pose.translations[:, sk.parents[1:]]
    )
    assert np.abs(on_parent - pose.joints[:, 1:]).max() < 1e-12


def test_the_zero_pose_is_the_rest_pose_exactly(poser, female):
    pose = poser.kinematics.pose(np.zeros(poser.skeleton.n_dofs))
    assert np.array_equal(pose.rotations[0], np.broadcast_to(np.eye(3), pose.rotations[0].shape))
    assert np.array_equal(pose.translations[0], np.zeros_like(pose.translations[0]))
    for method in ("lbs", "dqs"):
        assert np.array_equal(poser.pose(skinning=method).vertices, female.vertices)


def test_a_90_degree_elbow_puts_the_wrist_where_the_forearm_says(poser):
    sk = poser.skeleton
    k = sk.dof_index("forearm_l.flexion")
    posed = poser.pose(clinical={"forearm_l.flexion": np.pi / 2})
    shoulder, elbow, wrist = (posed.joints[sk.index(n)] for n in ("upper_arm_l", "forearm_l", "hand_l"))
    forearm = np.linalg.norm(sk.joints[sk.index("hand_l")] - sk.joints[sk.index("forearm_l")])
    assert np.linalg.norm(wrist - elbow) == pytest.approx(forearm, abs=1e-12)
    upper, lower = shoulder - elbow, wrist - elbow
    inner = np.degrees(np.arccos(upper @ lower / np.linalg.norm(upper) / np.linalg.norm(lower)))
    assert inner == pytest.approx(90.0, abs=1e-9)  # the hinge keeps both bones in its plane
    rest_dir = sk.joints[sk.index("hand_l")] - sk.joints[sk.index("forearm_l")]
    turned = axis_rotations(sk.dof_axes[[k]], np.array([np.pi / 2 - sk.rest[k]]))[0] @ rest_dir
    assert np.allclose(wrist, elbow + turned, atol=1e-12)
    assert wrist[2] > sk.joints[sk.index("hand_l")][2]  # flexion brings the hand forward


@pytest.mark.parametrize(
    "dof, part, axis, sign",
    [
        ("thoracic_12.flexion", "head", 2, +1),  # forward
        ("lumbar_3.lateral_bending", "head", 0, +1),  # to the body's left
        ("upper_arm_l.abduction", "hand_l", 1, +1),  # up
        ("upper_arm_r.abduction", "hand_r", 1, +1),
        ("upper_arm_l.flexion", "hand_l", 2, +1),  # forward
        ("thigh_l.flexion", "foot_l", 2, +1),
        ("shank_r.flexion", "foot_r", 2, -1),  # back
        ("foot_l.dorsiflexion", "toes_l", 1, +1),  # toes up
        ("jaw.depression", "jaw", 1, -1),  # chin down
    ],
)
def test_positive_angles_move_the_body_the_anatomical_way(poser, dof, part, axis, sign):
    sk = poser.skeleton
    q = np.zeros(sk.n_dofs)
    q[sk.dof_index(dof)] = np.radians(20)
    moved = forward_kinematics(sk, q).tails[0, sk.index(part)] - sk.tails[sk.index(part)]
    assert sign * moved[axis] > 0.2 * np.linalg.norm(moved)


def test_batches_equal_single_poses(poser, random_angles):
    many = poser.kinematics.pose(random_angles[:5])
    for p in range(5):
        one = poser.kinematics.pose(random_angles[p])
        assert np.allclose(one.rotations[0], many.rotations[p], atol=1e-14)
        assert np.allclose(one.translations[0], many.translations[p], atol=1e-14)
    assert poser.kinematics.pose(random_angles).matrices.shape == (200, 65, 4, 4)


def test_root_transform_moves_the_whole_skeleton(poser, random_angles):
    turn = np.eye(4)
    turn[:3, :3] = axis_rotations(np.array([[0.0, 1.0, 0.0]]), np.array([0.7]))[0]
    turn[:3, 3] = [0.1, 0.2, -0.3]
    plain = poser.kinematics.pose(random_angles[:3])
    moved = poser.kinematics.pose(random_angles[:3], root=turn)
    expect = np.einsum("ij,pnj->pni", turn[:3, :3], plain.joints) + turn[:3, 3]
    assert np.allclose(moved.joints, expect, atol=1e-12)


def test_limits_are_reported_clipped_or_refused(poser):
    sk = poser.skeleton
    q = np.zeros(sk.n_dofs)
    k = sk.dof_index("shank_l.flexion")
    q[k] = sk.upper[k] + 0.3
    mask = limit_violations(sk, q)
    assert mask.sum() == 1 and mask[k]
    with pytest.raises(HitogataError, match=r"shank_l.flexion = 152.2° clinical: allowed 0.0…135.0°"):
        forward_kinematics(sk, q, limits="raise")
    clipped = Kinematics(sk).check_limits(q, "clamp")
    assert clipped[k] == sk.upper[k]
    ignored = forward_kinematics(sk, q)  # the default poses as given
    assert not np.allclose(ignored.rotations, forward_kinematics(sk, clipped, limits="ignore").rotations)
    with pytest.raises(HitogataError, match="limits = 'sometimes'"):
        forward_kinematics(sk, q, limits="sometimes")
    with pytest.raises(HitogataError, match="angles of shape"):
        forward_kinematics(sk, q[:-1])


@pytest.mark.parametrize("side, lateral", [("l", 1.0), ("r", -1.0)])
def test_clinical_shoulder_flexion_and_abduction_move_the_arm_in_the_body_planes(poser, side, lateral):
    """From the anatomical position (arm hanging), flexion swings the arm forward in the sagittal plane
    and abduction out to the side in the frontal plane, although the rest pose is an A-pose."""
    sk = poser.skeleton
    part = sk.index(f"upper_arm_{side}")

    def arm_direction(**clinical_degrees):
        q = poser.angles(clinical={f"upper_arm_{side}.{k}": np.radians(v) for k, v in clinical_degrees.items()})
        pose = poser.kinematics.pose(q[None])
        d = pose.tails[0, part] - pose.joints[0, part]
        return d / np.linalg.norm(d)

    hanging = arm_direction(abduction=0)
    assert hanging[1] < -0.97  # down along the trunk
    forward = arm_direction(abduction=0, flexion=90)
    assert forward[2] > 0.97 and abs(forward[0]) < 0.2  # straight ahead, not across the chest
    raised = arm_direction(abduction=0, flexion=120)
    assert raised[1] > 0.4 and raised[2] > 0.4 and abs(raised[0]) < 0.2
    side_on = arm_direction(abduction=90)
    assert side_on[0] * lateral > 0.97  # out to its own side
