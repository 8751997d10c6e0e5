"""Contraction → joint angles by eq. 1 and 2, the antagonists following, and back."""

import warnings

import numpy as np
import pytest

from hitogata.errors import HitogataError
from hitogata.muscles.activation import (
    Drive,
    MuscleLimitWarning,
    angles_from_muscles,
    contractions_of,
    muscle_lengths,
)
from hitogata.muscles.equations import flexion_angle, rotation_angle
from hitogata.posing import Poser


@pytest.fixture(scope="module")
def muscles(male):
    return Poser.from_body(male).muscles


def admissible_angles(ms, k, n, rng):
    """Random muscle angles Θ inside both the joints' range and eq. 1/2's reach (off the edges)."""
    lo, hi = max(ms.low[k], ms.reach_low[k]), min(ms.high[k], ms.reach_high[k])
    return rng.uniform(lo + 1e-3, hi - 1e-3, n)


def test_contraction_angle_length_round_trip_for_every_muscle(muscles):
    ms, rng = muscles, np.random.default_rng(11)
    for k, name in enumerate(ms.names):
        theta = admissible_angles(ms, k, 25, rng)
        q = np.where(theta[:, None] >= 0, theta[:, None] * ms.share_pos[k], theta[:, None] * ms.share_neg[k])
        length = muscle_lengths(ms, q)[:, k]
        contraction = 1.0 - length / ms.rest_length[k]
        drive = Drive(ms, [name])
        q_back = drive.angles(contraction[:, None])
        assert np.abs(q_back - q).max() < 1e-9, name
        assert np.abs(muscle_lengths(ms, q_back)[:, k] - length).max() < 1e-9, name
        assert np.abs(contractions_of(ms, q_back)[:, k] - contraction).max() < 1e-9, name


def test_eq1_and_eq2_give_the_angles_exactly(muscles):
    ms = muscles
    b = ms.index("biceps_brachii_l")
    c = 0.12
    q = angles_from_muscles(ms, {"biceps_brachii_l": c})
    theta = flexion_angle(ms.d1[b], ms.d2[b], ms.rest_length[b] * (1 - c))  # eq. 1
    k = ms.skeleton.dof_index("forearm_l.flexion")
    assert q[k] == pytest.approx((theta - ms.theta0[b]) * ms.kappa[b], abs=1e-15)
    assert q[k] > 0  # the biceps flexes
    p = ms.index("pronator_teres_r")
    q = angles_from_muscles(ms, {"pronator_teres_r": 0.01})
    phi = rotation_angle(ms.rest_length[p] * 0.99, ms.height[p], ms.radius[p])  # eq. 2
    k = ms.skeleton.dof_index("forearm_r.pronation")
    assert q[k] == pytest.approx((phi - ms.phi0[p]) * ms.s[p], abs=1e-15)
    assert q[k] > 0  # the pronator pronates
    assert np.count_nonzero(q) == 1


def test_antagonists_follow_from_the_angles(muscles):
    ms = muscles
    q = angles_from_muscles(ms, {"quadriceps_r": 0.1})  # shorten the knee extensor
    lengths = muscle_lengths(ms, q)[0]
    quad, ham = ms.index("quadriceps_r"), ms.index("hamstrings_r")
    assert lengths[quad] == pytest.approx(0.9 * ms.rest_length[quad], rel=1e-12)
    assert lengths[ham] > ms.rest_length[ham]  # the knee straightens: the flexor lengthens
    back = angles_from_muscles(ms, lengths={"hamstrings_r": lengths[ham]})  # and says the same angle
    assert np.allclose(back, q, atol=1e-12)
    untouched = np.ones(len(ms.names), bool)
    untouched[[quad, ham]] = False
    assert np.allclose(lengths[untouched], ms.rest_length[untouched], rtol=1e-12)


def test_a_trunk_muscle_bends_every_vertebra_by_its_share(muscles):
    ms = muscles
    sk = ms.skeleton
    ra = ms.index("rectus_abdominis_r")
    q = angles_from_muscles(ms, {"rectus_abdominis_r": 0.15})
    dofs = ms.dofs(ra)
    assert np.all(q[dofs] > 0) and np.count_nonzero(q) == len(dofs)
    assert np.allclose(q[dofs] / q[dofs].sum(), sk.upper[dofs] / sk.upper[dofs].sum())
    full = muscle_lengths(ms, sk.upper * (ms.gather[ra] > 0))[0, ra]  # every vertebra at its limit
    q_full = angles_from_muscles(ms, lengths={"rectus_abdominis_r": full})
    assert np.allclose(q_full[dofs], sk.upper[dofs], atol=1e-9)  # they reach their limits together
    es = angles_from_muscles(ms, {"erector_spinae_l": 0.05})
    assert np.all(es[dofs] < 0)  # the erector spinae extends


def test_one_dof_one_driver(muscles):
    with pytest.raises(HitogataError, match="both move forearm_l.flexion: give one"):
        angles_from_muscles(muscles, {"biceps_brachii_l": 0.1, "triceps_brachii_l": -0.1})
    with pytest.raises(HitogataError, match="both move lumbar_5.flexion"):
        angles_from_muscles(muscles, {"rectus_abdominis_l": 0.1, "rectus_abdominis_r": 0.1})
    with pytest.raises(HitogataError, match="a contraction or a length, not both"):
        angles_from_muscles(muscles, {"deltoid_l": 0.1}, lengths={"deltoid_l": 0.1})
    with pytest.raises(HitogataError, match="no muscle named 'bicep_l'"):
        angles_from_muscles(muscles, {"bicep_l": 0.1})


def test_edges_raise_or_clamp_with_a_warning_never_nan(muscles):
    ms = muscles
    with pytest.raises(HitogataError) as err:
        angles_from_muscles(ms, {"biceps_brachii_l": 0.9})
    assert "biceps_brachii_l" in str(err.value) and "\n" not in str(err.value)
    with pytest.raises(HitogataError, match=r"supinator_l.*eq. 2 needs l >= d.*contractions <="):
        angles_from_muscles(ms, {"supinator_l": 0.5})
    with pytest.raises(HitogataError, match=r"triceps_brachii_l.*eq. 1 needs"):
        angles_from_muscles(ms, {"triceps_brachii_l": -5.0})
    sk = ms.skeleton
    for name, c in [("biceps_brachii_l", 0.9), ("supinator_l", 0.5), ("triceps_brachii_l", -5.0), ("iliopsoas_r", 2.0)]:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            q = angles_from_muscles(ms, {name: c}, on_limit="clamp")
        assert any(issubclass(w.category, MuscleLimitWarning) and name in str(w.message) for w in caught)
        assert np.all(np.isfinite(q)) and np.all(q >= sk.lower - 1e-12) and np.all(q <= sk.upper + 1e-12)
    with pytest.raises(HitogataError, match="finite"):
        angles_from_muscles(ms, {"deltoid_r": float("nan")}, on_limit="clamp")


def test_lengths_beyond_a_muscles_reach_raise_or_clamp(muscles):
    ms = muscles
    k = ms.index("triceps_brachii_l")
    q = np.zeros(ms.skeleton.n_dofs)
    q[ms.dofs(k)] = ms.reach_high[k] + 0.2  # past the triangle's straight line (a limit-ignoring pose)
    with pytest.raises(HitogataError, match="beyond what it can span"):
        muscle_lengths(ms, q)
    with pytest.warns(MuscleLimitWarning):
        lengths = muscle_lengths(ms, q, on_limit="clamp")
    assert np.all(np.isfinite(lengths))


def test_batched_drive_equals_single_calls(muscles):
    ms = muscles
    names = ["biceps_brachii_l", "external_oblique_r", "flexor_digitorum_superficialis_l", "gastrocnemius_r"]
    rng = np.random.default_rng(5)
    values = rng.uniform(-0.01, 0.02, (50, len(names)))
    many = Drive(ms, names).angles(values)
    for p in (0, 17, 49):
        one = angles_from_muscles(ms, dict(zip(names, values[p])))
        assert np.allclose(many[p], one, atol=1e-15)
    sk = ms.skeleton
    fingers = [sk.dof_index(f"{f}_proximal_l.flexion") for f in ("index", "middle", "ring", "little")]
    assert np.allclose(many[:, fingers], many[:, fingers[:1]])  # one flexor, four fingers alike
