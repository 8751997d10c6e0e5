"""The quasi-statics' accelerations: Chebyshev's weights, and that its steps land where plain steps do."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from hitogata.dynamics.quasistatic import HELD, Chebyshev, QuasiStatic
from hitogata.fem.verify.box_mesh import box_mesh


def test_chebyshev_weights_jump_then_settle_at_the_optimal_relaxation():
    rho = HELD.spectral_radius
    weights = [1.0]
    for step in range(400):
        weights.append(HELD.weight(step, weights[-1]))
    weights = weights[1:]
    assert weights[:HELD.plain_steps] == [1.0] * HELD.plain_steps
    assert weights[HELD.plain_steps] == pytest.approx(2.0 / (2.0 - rho**2))
    assert np.all(np.diff(weights[HELD.plain_steps:]) <= 0)  # falling from 2/(2 - ρ²) ...
    assert weights[-1] == pytest.approx(2.0 / (1.0 + np.sqrt(1.0 - rho**2)), rel=1e-12)  # ... to SOR's optimum
    for bad in ({"spectral_radius": 1.0}, {"spectral_radius": 0.0}, {"plain_steps": 0}):
        with pytest.raises(ValueError):
            Chebyshev(**bad)


@pytest.fixture(scope="module")
def bent_bar() -> tuple[QuasiStatic, np.ndarray]:
    """A soft bar 30 cm long held at both ends, its far end carried 10 cm sideways and turned 70°."""
    points, elements = box_mesh((0.3, 0.04, 0.04), (15, 2, 2))
    base, tip = np.flatnonzero(points[:, 0] < 1e-9), np.flatnonzero(points[:, 0] > 0.3 - 1e-9)
    statics = QuasiStatic(points, elements, 20e3, 0.45, np.concatenate([base, tip]), np.ones(len(elements), int),
                          (1,))
    x = points.copy()
    x[tip] = Rotation.from_euler("z", 70, degrees=True).apply(points[tip] - [0.3, 0.0, 0.0]) + [0.2, 0.1, 0.0]
    return statics, x


def test_chebyshev_steps_land_where_plain_steps_do(bent_bar):
    statics, x = bent_bar
    tolerance = 1e-9  # m
    fast, fast_size = statics.solve(x, iterations=160, tolerance=tolerance, acceleration=HELD)
    _, slow_size = statics.solve(x, iterations=160, tolerance=tolerance, acceleration=None)
    plain, plain_size = statics.solve(x, iterations=4000, tolerance=tolerance, acceleration=None)
    assert fast_size <= tolerance and plain_size <= tolerance
    assert slow_size > 1000 * tolerance  # plain steps are far from done where Chebyshev's are
    # both stop within a step of the tolerance, each a few steps' worth from the equilibrium
    np.testing.assert_allclose(fast, plain, atol=1e-7)


def test_chebyshev_steps_are_not_moved_by_round_off(bent_bar):
    statics, x = bent_bar
    nudged = x * (1.0 + 1e-14 * np.random.default_rng(0).standard_normal(x.shape))
    a, _ = statics.solve(x, iterations=400, tolerance=1e-9, acceleration=HELD)
    b, _ = statics.solve(nudged, iterations=400, tolerance=1e-9, acceleration=HELD)
    assert np.abs(a - b).max() < 1e-10
