"""Self-contact through a motion (`simulate(..., contact=True)`, `dynamics.motion_contact`): the IPC barrier
frame to frame keeps the forearm's skin out of the upper arm's as the elbow flexes to 150°, where the
motion without it keeps skinning's crossings; and `hitogata simulate --contact`."""

from __future__ import annotations

import numpy as np
import pytest

from hitogata import cli
from hitogata.dynamics.motion import simulate
from hitogata.dynamics.run import JUMP_SPEED, contact_figures
from hitogata.dynamics.single_pose import elastic_dynamics
from hitogata.dynamics.scenario import load_scenario, shipped_scenarios
from hitogata.geometry import self_intersections, surface_integrity

RATE = 10.0  # frames/s: the shipped scenario's flexion, 40° at 0 s → 150° at 0.9 s, in frames up to 19° apart


@pytest.fixture(scope="module")
def flexion(female):
    """The whole default female body (the model `elastic_pose` shares) flexing the left elbow, without and
    with contact."""
    scenario = load_scenario(shipped_scenarios()["elbow_flexion_body"])
    calls: list[tuple[int, int]] = []
    runs = {contact: simulate(elastic_dynamics(female), scenario.timeline, 0.9, RATE, contact=contact,
                              progress=(lambda done, total: calls.append((done, total))) if contact else None)
            for contact in (False, True)}
    return runs, calls


@pytest.mark.slow
def test_contact_holds_through_an_elbow_flexion(female, flexion):
    runs, calls = flexion
    faces = female.faces
    rest = set(map(tuple, self_intersections(female.vertices, faces).tolist()))
    test = runs[True].dynamics.contact

    def per_frame(skins: np.ndarray) -> list[tuple[int, int]]:
        """(new crossing pairs beyond the rest body's, vertices inside another part) per frame."""
        return [(len(set(map(tuple, self_intersections(x, faces).tolist())) - rest), len(test.penetrations(x)))
                for x in skins]

    plain, held = runs[False], runs[True]
    assert calls == [(n, 20) for n in range(1, 21)]  # progress: 10 steps, then 10 frames' contact
    np.testing.assert_array_equal(plain.skinned_skin, held.skinned_skin)  # the same motion, its skin resolved
    # without contact skinning's crossings stay (the forearm's skin through the upper arm's); with it none
    assert per_frame(plain.skin) == [(0, 0), (0, 0), (0, 0), (0, 0), (12, 0), (29, 6), (41, 16), (53, 27), (61, 34),
                                     (134, 78)]
    assert per_frame(held.skin) == [(0, 0)] * 10
    took = held.contact
    assert took is not None and plain.contact is None
    # the free skin grows with the crease; every frame started from the last one's skin (none from rest again)
    assert took.free.tolist() == [0, 0, 0, 0, 101, 157, 184, 218, 519, 636]
    assert took.from_rest.tolist() == [True] + [False] * 9
    assert contact_figures(took)["frames_meeting"] == 6
    worst = surface_integrity(female.vertices, faces, held.skin, held.times, held.skinned_skin).worst()
    assert worst["self_intersections_beyond_skinning"] == 0 and worst["below_floor_beyond_skinning"] == 0
    # no jump, no tear: the elastic displacement changes at most 10 mm a frame
    assert round(worst["largest_elastic_jump_speed_m_s"], 2) == 0.10 < JUMP_SPEED
    # left: the crease's forearm skin pressed against the upper arm folds 4 neighbouring triangle pairs over
    # at 150° (skin of one group nearer than barrier_contact.SAME_APART at rest, which the barrier lets meet)
    assert (worst["folds_beyond_skinning"], worst["new_folds_time_s"]) == (4, 0.9)


def test_simulate_takes_contact(capsys):
    """`hitogata simulate --contact` asks the run for contact (default off); a value given to it is one
    line, exit 2."""
    parse = cli.build_parser("simulate").parse_args
    assert parse(["simulate", "rectus_stretch", "--contact"]).contact is True
    assert parse(["simulate", "rectus_stretch"]).contact is False
    assert cli.main(["simulate", "rectus_stretch", "--contact=yes"]) == 2
    assert capsys.readouterr().err.splitlines() == [
        "hitogata: error: argument --contact: ignored explicit argument 'yes'"]
