"""Skinning: LBS and DQS against plain per-vertex formulas, rigid parts, twist, batches."""

import numpy as np
import pytest

from hitogata.errors import HitogataError
from hitogata.posing import Poser, pose_body
from hitogata.posing.skinning import dual_quaternions, skin_vertices
from hitogata.geometry.rotations import matrix_to_quaternion


@pytest.fixture(scope="module")
def poser(female) -> Poser:
    return Poser.from_body(female)


@pytest.fixture(scope="module")
def pose(poser):
    sk = poser.skeleton
    q = np.random.default_rng(2).uniform(sk.lower, sk.upper, (3, sk.n_dofs))
    return poser.kinematics.pose(q)


def quat_mul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])  # fmt: skip


def test_lbs_equals_the_per_vertex_sum(poser, pose):
    w = poser.skin.weights.toarray()
    rest = poser.skin.rest
    posed = skin_vertices(poser.skin, pose.rotations, pose.translations, "lbs")
    for p in range(len(posed)):
        for v in np.random.default_rng(p).choice(len(rest), 200, replace=False):
            expect = sum(
                w[v, k] * (pose.rotations[p, k] @ rest[v] + pose.translations[p, k]) for k in np.flatnonzero(w[v])
            )
            assert np.allclose(posed[p, v], expect, atol=1e-12)


def test_dqs_equals_the_per_vertex_dual_quaternion_blend(poser, pose):
    w = poser.skin.weights.toarray()
    rest = poser.skin.rest
    dq = dual_quaternions(poser.skin, pose.rotations, pose.translations)
    posed = skin_vertices(poser.skin, pose.rotations, pose.translations, "dqs")
    for p in range(len(posed)):
        for v in np.random.default_rng(10 + p).choice(len(rest), 200, replace=False):
            b = sum(w[v, k] * dq[p, k] for k in np.flatnonzero(w[v]))
            real, dual = b[:4] / np.linalg.norm(b[:4]), b[4:] / np.linalg.norm(b[:4])
            conj = real * np.array([1, -1, -1, -1])
            turned = quat_mul(quat_mul(real, np.concatenate([[0.0], rest[v]])), conj)[1:]
            moved = 2.0 * quat_mul(dual, conj)[1:]
            assert np.allclose(posed[p, v], turned + moved, atol=1e-12)


def test_quaternions_and_their_hemispheres(poser, pose):
    q = matrix_to_quaternion(pose.rotations)
    w, x, y, z = np.moveaxis(q, -1, 0)
    rebuilt = np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
    ], -2)  # fmt: skip
    assert np.allclose(rebuilt, pose.rotations, atol=1e-12)
    dq = dual_quaternions(poser.skin, pose.rotations, pose.translations)
    parents = poser.skeleton.parents
    assert np.all(np.einsum("pni,pni->pn", dq[:, 1:, :4], dq[:, parents[1:], :4]) >= 0)


def test_rigid_skin_moves_rigidly_with_both_methods(poser, pose):
    w = poser.skin.weights
    single = np.flatnonzero(np.diff(w.indptr) == 1)
    part = w.indices[w.indptr[single]]
    rest = poser.skin.rest[single]
    expect = np.einsum("pnij,nj->pni", pose.rotations[:, part], rest) + pose.translations[:, part]
    for method in ("lbs", "dqs"):
        posed = skin_vertices(poser.skin, pose.rotations, pose.translations, method)[:, single]
        assert np.abs(posed - expect).max() < 1e-12


def test_dqs_keeps_a_twisted_forearm_round_where_lbs_pinches_it(poser):
    sk, w = poser.skeleton, poser.skin.weights
    arm, fore = sk.index("upper_arm_l"), sk.index("forearm_l")
    share = w[:, fore].toarray().ravel()
    elbow = np.flatnonzero((share > 0.35) & (share < 0.65) & (w[:, arm].toarray().ravel() > 0.3))
    assert len(elbow) > 10
    centre, axis = sk.joints[fore], sk.frames[fore][:, 1]

    def radius(points, c, a):
        d = points - c
        return np.linalg.norm(d - np.outer(d @ a, a), axis=1)

    twist = {"forearm_l.pronation": np.radians(80), "upper_arm_l.internal_rotation": np.radians(-80)}
    ratios = {}
    for method in ("lbs", "dqs"):
        posed = poser.pose(angles=twist, skinning=method)
        c = posed.joints[fore]
        a = posed.pose.frames[0, fore][:, 1]
        ratios[method] = np.median(radius(posed.vertices[elbow], c, a) / radius(poser.skin.rest[elbow], centre, axis))
    assert ratios["lbs"] < 0.85 < 0.95 < ratios["dqs"] < 1.05


def test_batches_equal_single_poses_and_extreme_poses_stay_finite(poser, pose):
    for method in ("lbs", "dqs"):
        many = skin_vertices(poser.skin, pose.rotations, pose.translations, method)
        one = skin_vertices(poser.skin, pose.rotations[1:2], pose.translations[1:2], method)
        assert np.allclose(many[1], one[0], atol=1e-13)
    sk = poser.skeleton
    for corner in (sk.lower, sk.upper):
        for method in ("lbs", "dqs"):
            assert np.all(np.isfinite(poser.pose_many(corner, skinning=method)))
    with pytest.raises(HitogataError, match="skinning = 'blend'"):
        skin_vertices(poser.skin, pose.rotations, pose.translations, "blend")


def test_pose_body_in_one_call(female):
    posed = pose_body(female, contractions={"biceps_brachii_r": 0.1}, skinning="dqs")
    assert posed.vertices.shape == female.vertices.shape and posed.faces is female.faces
    assert posed.angle("forearm_r.flexion") > 0
    assert (
        posed.clinical[posed.skeleton.dof_index("forearm_r.flexion")]
        > posed.skeleton.rest[posed.skeleton.dof_index("forearm_r.flexion")]
    )
    bones, lines = posed.bones, posed.muscle_lines
    assert bones.shape == (65, 2, 3) and lines.shape == (len(posed.muscle_names), 2, 3)
    biceps = posed.muscles.index("biceps_brachii_r")
    length = np.linalg.norm(lines[biceps, 1] - lines[biceps, 0])
    rest = np.linalg.norm(posed.muscles.insertions[biceps] - posed.muscles.origins[biceps])
    assert length < rest  # the drawn biceps shortens too
    with pytest.raises(HitogataError, match="set both by an angle and by muscle 'biceps_brachii_r'"):
        pose_body(female, contractions={"biceps_brachii_r": 0.1}, angles={"forearm_r.flexion": 0.2})
