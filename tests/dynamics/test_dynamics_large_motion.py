"""Large motion: the extreme poses the joint limits allow, against plain linear blend skinning.

For each pose the elastic body (DQS + the quasi-static correction) must
invert no element, keep every tissue region within 3 % of its rest volume
and distort the skin less than LBS, which inverts elements in every one of
these poses.
"""

import numpy as np
import pytest

from hitogata.dynamics import BodyDynamics, compare_pose
from hitogata.dynamics.quasistatic import corner_volumes, rotate
from hitogata.elastic import build_elastic_model

TRUNK = [f"lumbar_{i}" for i in range(1, 6)] + [f"thoracic_{i}" for i in range(1, 13)]
BODY_POSES = {
    "elbow 150°": {"forearm_l.flexion": 150},
    "knee 130°": {"shank_l.flexion": 130},
    "hip flexion 120°": {"thigh_l.flexion": 120},
    "shoulder abduction 170°": {"upper_arm_l.abduction": 120, "scapula_l.upward_rotation": 50},
}


def clinical_pose(skeleton, clinical: dict[str, float]) -> np.ndarray:
    q = np.zeros(skeleton.n_dofs)
    for name, degrees in clinical.items():
        k = skeleton.dof_index(name)
        q[k] = np.radians(degrees) - skeleton.rest[k]
    assert np.all(q >= skeleton.lower - 1e-9) and np.all(q <= skeleton.upper + 1e-9), "within the joint limits"
    return q


@pytest.fixture(scope="module")
def body_dynamics(male):
    from hitogata.skin.single_pose import elastic_dynamics

    return elastic_dynamics(male, n_modes=2)  # the whole body at 40 mm, 2 modes; built once per session for the male


@pytest.fixture(scope="module")
def trunk_dynamics(female):
    return BodyDynamics.build(female, build_elastic_model(female, extent="trunk", n_modes=2))


def check(figures) -> None:
    lbs, elastic = figures["lbs"], figures["elastic"]
    print("\n" + "\n".join(f.line() for f in figures.values()))
    assert lbs.inverted > 0
    assert elastic.inverted == 0
    assert max(abs(v) for v in elastic.region_change.values()) < 0.03
    assert elastic.skin_distortion < lbs.skin_distortion


def test_trunk_flexion_80(trunk_dynamics):
    sk = trunk_dynamics.poser.skeleton
    q = np.zeros(sk.n_dofs)
    for part in TRUNK:
        k = sk.dof_index(f"{part}.flexion")
        q[k] = sk.upper[k]
    assert np.degrees(q[[sk.dof_index(f"{p}.flexion") for p in TRUNK]].sum()) == pytest.approx(80, abs=0.5)
    figures = compare_pose(trunk_dynamics, q)
    assert figures["lbs"].region_change["viscera"] < -0.1  # LBS loses a tenth of the viscera
    check(figures)


@pytest.mark.parametrize("name", BODY_POSES)
def test_whole_body_extreme_poses(body_dynamics, name):
    q = clinical_pose(body_dynamics.poser.skeleton, BODY_POSES[name])
    # from rest, 40 steps leave the hip flexion short of equilibrium: its skin distortion 0.198, or 0.193 with
    # other round-off (LBS 0.193); 80 steps reach 0.182
    figures = compare_pose(body_dynamics, q, iterations=80)
    check(figures)


def test_hip_flexion_warm_started_from_a_knee_pose(body_dynamics):
    """The quasi-statics warm-start their rotations from the previous pose; from the knee's, the
    hip's crease left one element inverted (-0.2 % of rest) until the untangler priced inversion
    above flatness."""
    sk = body_dynamics.poser.skeleton
    warm = body_dynamics.statics.warm_start()
    for clinical in (BODY_POSES["knee 130°"], BODY_POSES["hip flexion 120°"]):
        pose = body_dynamics.poser.kinematics.pose(clinical_pose(sk, clinical))
        g, R = body_dynamics.rig.pose(pose.rotations, pose.translations)
        delta, _ = body_dynamics.quasi_static(g[0], R[0], None, None, 40, warm)
    x = g[0] + rotate(R[0], delta)
    model = body_dynamics.model
    ratio = corner_volumes(x, model.elements) / corner_volumes(model.points, model.elements)
    assert ratio.min() > 0.0199
