"""Eq. 1 and eq. 2 against hand-computed triangles and helices, with their domain edges."""

import math

import numpy as np
import pytest

from hitogata.errors import HitogataError
from hitogata.muscles.equations import (
    flexion_angle,
    flexion_domain,
    flexion_length,
    rotation_angle,
    rotation_length,
)


@pytest.mark.parametrize(
    "d1, d2, length, degrees",
    [
        (3.0, 4.0, 5.0, 90.0),  # the 3-4-5 right triangle
        (1.0, 1.0, 1.0, 60.0),  # equilateral
        (1.0, 1.0, math.sqrt(2.0), 90.0),
        (2.0, 2.0, 2.0 * math.sqrt(3.0), 120.0),  # isosceles, 30° base angles
        (0.3, 0.25, math.sqrt(0.3**2 + 0.25**2 - 2 * 0.3 * 0.25 * math.cos(math.radians(37))), 37.0),
    ],
)
def test_eq1_hand_computed_triangles(d1, d2, length, degrees):
    theta = flexion_angle(d1, d2, length)
    assert math.degrees(theta) == pytest.approx(degrees, abs=1e-12)
    assert flexion_length(d1, d2, theta) == pytest.approx(length, abs=1e-15)


def test_eq1_domain_edges_are_straight_and_folded_joints():
    assert flexion_domain(0.3, 0.1) == pytest.approx((0.2, 0.4))
    assert flexion_angle(0.3, 0.1, 0.4) == pytest.approx(math.pi, abs=1e-12)  # l = d1 + d2: straight
    assert flexion_angle(0.3, 0.1, 0.2) == pytest.approx(0.0, abs=1e-7)  # l = |d1 − d2|: folded
    assert flexion_angle(0.3, 0.1, 0.4 * (1 + 1e-13)) == pytest.approx(math.pi)  # rounding is on the edge


@pytest.mark.parametrize("length", [0.45, 0.19, -0.1])
def test_eq1_outside_its_domain_is_an_error_or_a_clamp_never_nan(length):
    with pytest.raises(HitogataError) as err:
        flexion_angle(0.3, 0.1, length)
    assert "outside the domain [0.2, 0.4]" in str(err.value) and "\n" not in str(err.value)
    clamped = flexion_angle(0.3, 0.1, length, clamp=True)
    assert clamped == (math.pi if length > 0.4 else 0.0)
    assert not np.isnan(clamped)


def test_eq1_rejects_non_numbers_and_zero_arms():
    with pytest.raises(HitogataError, match="finite"):
        flexion_angle(0.3, 0.1, float("nan"), clamp=True)
    with pytest.raises(HitogataError, match="d1 > 0"):
        flexion_angle(0.0, 0.1, 0.1)


@pytest.mark.parametrize(
    "length, d, r, phi",
    [
        (5.0, 3.0, 2.0, 2.0),  # unrolled: the 3-4-5 triangle, rφ = 4
        (math.hypot(0.1, 0.02 * math.pi), 0.1, 0.02, math.pi),  # half a turn round a 2 cm bone over 10 cm
        (math.hypot(0.05, 0.03 * 2 * math.pi), 0.05, 0.03, 2 * math.pi),  # one full turn
        (0.2, 0.0, 0.05, 4.0),  # no height: wound flat, φ = l / r
    ],
)
def test_eq2_hand_computed_helices(length, d, r, phi):
    assert rotation_angle(length, d, r) == pytest.approx(phi, abs=1e-12)
    assert rotation_length(phi, d, r) == pytest.approx(length, abs=1e-15)


def test_eq2_helix_length_matches_an_integrated_helix():
    d, r, phi = 0.12, 0.015, 2.3
    t = np.linspace(0.0, 1.0, 200001)
    points = np.stack([r * np.cos(phi * t), r * np.sin(phi * t), d * t], axis=1)
    arc = np.linalg.norm(np.diff(points, axis=0), axis=1).sum()
    assert rotation_length(phi, d, r) == pytest.approx(arc, rel=1e-9)
    assert rotation_angle(arc, d, r) == pytest.approx(phi, rel=1e-6)


def test_eq2_domain_edge_is_an_unwound_muscle():
    assert rotation_angle(0.1, 0.1, 0.02) == 0.0  # l = d: straight along the cylinder
    with pytest.raises(HitogataError, match=r"eq. 2: helix length 0.09 m is outside the domain \[0.1, inf\]"):
        rotation_angle(0.09, 0.1, 0.02)
    assert rotation_angle(0.09, 0.1, 0.02, clamp=True) == 0.0
    with pytest.raises(HitogataError, match="radius r > 0"):
        rotation_angle(0.2, 0.1, 0.0)


def test_contraction_angle_length_round_trip_to_1e9():
    rng = np.random.default_rng(3)
    d1, d2 = rng.uniform(0.01, 0.4, 1000), rng.uniform(0.01, 0.4, 1000)
    lo, hi = flexion_domain(d1, d2)
    length = lo + rng.uniform(0.0, 1.0, 1000) * (hi - lo)
    assert np.abs(flexion_length(d1, d2, flexion_angle(d1, d2, length)) - length).max() < 1e-9
    theta = rng.uniform(0.0, np.pi, 1000)
    assert np.abs(flexion_angle(d1, d2, flexion_length(d1, d2, theta)) - theta).max() < 1e-6  # arccos at 0, π
    inner = theta[(theta > 0.01) & (theta < np.pi - 0.01)]
    d1i, d2i = d1[: len(inner)], d2[: len(inner)]
    assert np.abs(flexion_angle(d1i, d2i, flexion_length(d1i, d2i, inner)) - inner).max() < 1e-9
    d, r, phi = rng.uniform(0.0, 0.3, 1000), rng.uniform(0.005, 0.1, 1000), rng.uniform(0.0, 6.0, 1000)
    assert np.abs(rotation_angle(rotation_length(phi, d, r), d, r) - phi).max() < 1e-9
