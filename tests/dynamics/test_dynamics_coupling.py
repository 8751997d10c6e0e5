"""Coupling of skeleton and elastic body over time: rest exactness, settling, energy, Rayleigh decay."""

import dataclasses

import numpy as np
import pytest

from hitogata.dynamics import BodyDynamics, Keyframe, Timeline, simulate
from hitogata.dynamics.quasistatic import rotate
from hitogata.dynamics.rigging import joint_nodes
from hitogata.elastic import build_elastic_model
from hitogata.fem import no_modes

STRETCH = ("contraction", "rectus_abdominis_l")


@pytest.fixture(scope="module")
def model(female):
    return build_elastic_model(female, extent="trunk", element_size=60.0, n_modes=12)


@pytest.fixture(scope="module")
def dynamics(female, model):
    return BodyDynamics.build(female, model)


def ramp_and_hold(value: float, ramp: float = 0.2) -> Timeline:
    return Timeline.from_keyframes([Keyframe(0.0, {STRETCH: 0.0}), Keyframe(ramp, {STRETCH: value}, "linear")])


def test_no_contraction_gives_the_rest_shape_exactly(dynamics, female, model):
    still = Timeline.from_keyframes([Keyframe(0.0, {}), Keyframe(0.3, {})])
    motion = simulate(dynamics, still, duration=0.5, rate=20)
    assert np.abs(motion.elastic).max() < 1e-12
    assert np.array_equal(motion.nodes, np.broadcast_to(model.points.astype(np.float32), motion.nodes.shape))
    assert np.array_equal(motion.skin, np.broadcast_to(female.vertices.astype(np.float32), motion.skin.shape))
    assert np.abs(motion.q).max() < 1e-12
    # A muscle held at zero contraction: eq. 1's arccos at the rest length is exact to ~1e-8 rad.
    zero = Timeline.from_keyframes([Keyframe(0.0, {STRETCH: 0.0}), Keyframe(0.3, {STRETCH: 0.0})])
    motion = simulate(dynamics, zero, duration=0.5, rate=20)
    assert np.abs(motion.skin - female.vertices).max() < 1e-7


def modal_envelopes(motion, dynamics):
    """Per underdamped mode, the amplitude of its free oscillation about the quasi-static answer."""
    lam = dynamics.eigenvalues
    omega = np.sqrt(lam)
    zeta = (dynamics.model.alpha + dynamics.model.beta * lam) / (2 * omega)
    under = zeta < 1
    e, ed = (motion.q - motion.s)[:, under], motion.qd[:, under]
    w, z = omega[under], zeta[under]
    wd = w * np.sqrt(1 - z**2)
    return np.sqrt(e**2 + ((ed + z * w * e) / wd) ** 2), z * w


def test_a_clinical_keyframe_moves_from_the_rest_pose(dynamics):
    """No jump at t = 0: a shoulder keyed only later starts at its rest abduction (42°), elastic part zero."""
    k = dynamics.poser.skeleton.dof_index("upper_arm_l.abduction")
    rest = dynamics.poser.skeleton.rest[k]
    raise_arm = Timeline.from_keyframes([Keyframe(0.0, {}), Keyframe(0.2, {("clinical", "upper_arm_l.abduction"): rest + 0.3})])
    motion = simulate(dynamics, raise_arm, duration=0.2, rate=20)
    assert np.abs(motion.angles[0]).max() == 0.0 and np.abs(motion.elastic[0]).max() == 0.0
    assert motion.angles[-1][k] == pytest.approx(0.3)


def test_a_held_contraction_settles_at_the_rate_the_damping_ratios_give(dynamics):
    motion = simulate(dynamics, ramp_and_hold(-0.05), duration=3.0, rate=50, on_limit="clamp")
    after = motion.times >= 0.2 + 1e-9
    envelope, rate = modal_envelopes(motion, dynamics)
    t = motion.times[after] - motion.times[after][0]
    predicted = envelope[after][0] * np.exp(-rate * t[:, None])
    assert rate.min() > 0
    big = envelope[after][0] > 1e-6 * envelope[after][0].max()
    assert np.allclose(envelope[after][:, big], predicted[:, big], rtol=1e-6, atol=1e-12)
    # The dynamic part dies out: at the end the body is at its quasi-static answer.
    gap = np.linalg.norm(dynamics.superpose(motion.q[-1] - motion.s[-1]), axis=1).max()
    peak = np.linalg.norm(motion.elastic, axis=2).max()
    assert peak > 1e-3 and gap < 1e-3 * peak


def test_a_model_built_without_modes_is_the_quasi_static_part_and_takes_its_modes_later(dynamics, female, model):
    """Held postures need no modes: a model built with none moves as the full dynamics' quasi-static part
    (its elastic displacement less the modes' R Φ (q − s)); given the modes afterwards it is the full
    dynamics exactly."""
    bare = BodyDynamics.build(female, dataclasses.replace(model, modes=no_modes(len(model.points))))
    assert bare.eigenvalues.shape == (0,) and bare.vectors.shape == (len(model.points), 3, 0)
    ramp = ramp_and_hold(-0.05)
    quasi = simulate(bare, ramp, duration=0.3, rate=20, on_limit="clamp")
    full = simulate(dynamics, ramp, duration=0.3, rate=20, on_limit="clamp")
    _, node_rotations = dynamics.rig.pose(full.rotations, full.translations)
    modal = np.stack([rotate(r, dynamics.superpose(q - s)) for r, q, s in zip(node_rotations, full.q, full.s)])
    peak = np.linalg.norm(full.elastic, axis=2).max()
    assert peak > 1e-3 and np.linalg.norm(modal, axis=2).max() > 1e-2 * peak  # the modes do move it
    assert np.abs(quasi.elastic - (full.elastic - modal)).max() < 1e-5 * peak  # float32 frames
    given = bare.with_modes(model.modes)
    for name in ("vectors", "vectors32", "projector", "eigenvalues"):
        assert np.array_equal(getattr(given, name), getattr(dynamics, name)), name


def test_undamped_modal_dynamics_keeps_its_energy_for_10_s(female, model):
    free = BodyDynamics.build(female, dataclasses.replace(model, alpha=0.0, beta=0.0))
    motion = simulate(free, ramp_and_hold(-0.05, ramp=0.1), duration=10.0, rate=10, substeps=5,
                      on_limit="clamp")  # steps of 20 ms, a frame every 0.1 s
    after = motion.times >= 0.1 + 1e-9
    energy = 0.5 * np.sum(motion.qd**2 + free.eigenvalues * (motion.q - motion.s) ** 2, axis=1)[after]
    assert energy[0] > 0
    assert np.abs(energy / energy[0] - 1).max() < 1e-6


def test_bone_nodes_follow_their_parts(dynamics, model):
    motion = simulate(dynamics, ramp_and_hold(0.2, ramp=0.5), duration=0.6, rate=20, on_limit="clamp")
    corners = model.fixed_nodes[model.fixed_nodes < len(model.volume.nodes)]
    held = np.setdiff1d(corners, joint_nodes(dynamics.rig.weights, model.elements, model.fixed_nodes))
    assert len(held) > 0.5 * len(corners)  # all but the joints' cartilage nodes
    assert np.abs(motion.elastic[:, held]).max() < 1e-12  # modes are zero there, quasi-statics holds them
    weights = dynamics.rig.weights[held].toarray()
    rigid = held[weights.max(axis=1) == 1.0]
    part = weights.argmax(axis=1)[weights.max(axis=1) == 1.0]
    expected = np.einsum("nij,nj->ni", motion.rotations[-1, part], model.points[rigid]) + motion.translations[-1, part]
    # At 60 mm the bone capsules' surfaces carry few nodes: a dozen of them follow one part alone.
    assert len(rigid) >= 10 and np.abs(motion.nodes[-1, rigid] - expected).max() < 1e-6


def test_a_run_does_not_depend_on_what_was_solved_before(dynamics):
    """The quasi-statics' warm start belongs to a run (`simulate` makes its own), not to the model:
    the same run gives the same motion before and after another run and a lone solve."""
    k = dynamics.poser.skeleton.dof_index("upper_arm_l.abduction")
    rest = dynamics.poser.skeleton.rest[k]
    raise_arm = Timeline.from_keyframes([Keyframe(0.0, {}), Keyframe(0.3, {("clinical", "upper_arm_l.abduction"): rest + 0.6})])
    first = simulate(dynamics, raise_arm, duration=0.4, rate=20)
    simulate(dynamics, ramp_and_hold(-0.08), duration=0.4, rate=20)
    pose = dynamics.poser.kinematics.pose(first.angles[-1] * 1.5)
    g, R = dynamics.rig.pose(pose.rotations, pose.translations)
    dynamics.quasi_static(g[0], R[0], None, None, 10)
    again = simulate(dynamics, raise_arm, duration=0.4, rate=20)
    assert np.abs(first.elastic).max() > 1e-4  # the arm's raise moves the tissue
    np.testing.assert_array_equal(again.nodes, first.nodes)
    # A solve with a warm start carries it on; one without starts from rest each time.
    warm = dynamics.statics.warm_start()
    a, _ = dynamics.quasi_static(g[0], R[0], None, None, 3)
    dynamics.quasi_static(g[0], R[0], None, None, 3, warm)
    b, _ = dynamics.quasi_static(g[0], R[0], None, None, 3)
    c, _ = dynamics.quasi_static(g[0], R[0], None, None, 3, warm)
    np.testing.assert_array_equal(a, b)
    assert np.abs(c - a).max() > 0.0
