"""Every piece of the elastic body's mesh keeps a held node, so the quasi-statics always has an equilibrium
(a piece with no bone node at all goes with the skinning)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from hitogata.dynamics.rigging import anchored, boneless_nodes


def test_a_piece_hanging_on_released_joint_nodes_gets_its_bone_nodes_back():
    corners = np.array([[0, 1, 2, 3], [1, 2, 3, 4],  # piece one: node 0 held
                        [5, 6, 7, 8]])  # piece two: its bone nodes 5 and 6 were all released as joint nodes
    fixed = np.array([0, 4, 5, 6])
    held = np.array([0, 4])
    np.testing.assert_array_equal(anchored(held, fixed, corners), [0, 4, 5, 6])
    np.testing.assert_array_equal(anchored(np.array([0, 5]), fixed, corners), [0, 5])  # both held: unchanged


def test_a_piece_holding_no_bone_node_goes_with_the_skinning():
    """A tetrahedron joined to nothing (the male's 40 mm mesh has one in the skin) has no equilibrium: its
    nodes are held where the skinning puts them; a piece with a bone node, held or released, is not."""
    corners = np.array([[0, 1, 2, 3], [1, 2, 3, 4],  # a piece with bone node 0
                        [5, 6, 7, 8],  # a loose tetrahedron
                        [9, 10, 11, 12]])  # a piece whose one bone node (9) a joint released
    fixed = np.array([0, 9])
    np.testing.assert_array_equal(boneless_nodes(corners, 13, fixed), [5, 6, 7, 8])
    np.testing.assert_array_equal(boneless_nodes(corners[:2], 5, fixed), np.zeros(0, dtype=int))


@pytest.mark.slow
def test_the_male_posture_is_an_equilibrium_not_an_iteration_count(male):
    """With the male's loose tetrahedron held by the skinning, a held posture's quasi-statics converges: it
    stops at its tolerance before the step cap, and neither a tighter, longer solve nor a 1e-12 relative nudge
    of its input moves a node by 0.1 mm (the loose piece's round-off pivot had every male posture run to the
    cap, its answer a matter of round-off: a 1e-14 nudge moved nodes by 5-32 mm)."""
    from hitogata.dynamics.quality import STATIC_ITERATIONS
    from hitogata.dynamics.single_pose import elastic_dynamics
    from hitogata.skeleton.extreme_poses import extreme_poses

    dynamics = elastic_dynamics(male)
    statics = dynamics.statics
    poses = extreme_poses(dynamics.poser.skeleton)
    for name in ("shoulder abduction 170°", "trunk rotation 45°", "neck flexion 45°"):
        posed = dynamics.poser.pose(clinical=poses[name], skinning=dynamics.rig.method)
        skinned = dynamics.rig.pose(posed.pose.rotations, posed.pose.translations)[0][0, :len(statics.points)]
        x, size = statics.solve(skinned, iterations=STATIC_ITERATIONS)
        assert size <= 1e-5, name
        tight, _ = statics.solve(skinned, iterations=4 * STATIC_ITERATIONS, tolerance=1e-7)
        nudged, _ = statics.solve(skinned * (1.0 + 1e-12), iterations=STATIC_ITERATIONS)
        assert np.abs(tight - x).max() < 1e-4, name
        assert np.abs(nudged - x).max() < 1e-4, name


@pytest.mark.slow
def test_an_older_womans_elastic_body_holds_a_seated_posture():
    """A 76-year-old woman of the default stature and mass: a piece of her 40 mm mesh hung on joint nodes
    alone, and the quasi-statics' matrix was singular."""
    from hitogata.body import Body
    from hitogata.dynamics.single_pose import elastic_dynamics, elastic_pose

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        body = Body.from_measurements("female", 75.9, 1.65, 62.0)
    seated = {f"{part}_{side}.flexion": np.radians(90) for part in ("thigh", "shank") for side in "lr"}
    held = elastic_pose(elastic_dynamics(body), clinical=seated, contact=True)
    assert held.quality.inverted == 0
    assert np.isfinite(held.vertices).all()
    assert max(abs(v) for v in held.quality.region_change.values()) < 0.01  # tissue volume kept within 1 %
