"""Every piece of the elastic body's mesh keeps a held node, so the quasi-statics always has an equilibrium."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from hitogata.dynamics.rigging import anchored


def test_a_piece_hanging_on_released_joint_nodes_gets_its_bone_nodes_back():
    corners = np.array([[0, 1, 2, 3], [1, 2, 3, 4],  # piece one: node 0 held
                        [5, 6, 7, 8]])  # piece two: its bone nodes 5 and 6 were all released as joint nodes
    fixed = np.array([0, 4, 5, 6])
    held = np.array([0, 4])
    np.testing.assert_array_equal(anchored(held, fixed, corners), [0, 4, 5, 6])
    np.testing.assert_array_equal(anchored(np.array([0, 5]), fixed, corners), [0, 5])  # both held: unchanged


@pytest.mark.slow
def test_an_older_womans_elastic_body_holds_a_seated_posture():
    """A 76-year-old woman of the default stature and mass: a piece of her 40 mm mesh hung on joint nodes
    alone, and the quasi-statics' matrix was singular."""
    from hitogata.body import Body
    from hitogata.skin.single_pose import elastic_dynamics, elastic_pose

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        body = Body.from_measurements("female", 75.9, 1.65, 62.0)
    seated = {f"{part}_{side}.flexion": np.radians(90) for part in ("thigh", "shank") for side in "lr"}
    held = elastic_pose(elastic_dynamics(body), clinical=seated, contact=True)
    assert held.quality.inverted == 0
    assert np.isfinite(held.vertices).all()
    assert max(abs(v) for v in held.quality.region_change.values()) < 0.01  # tissue volume kept within 1 %
