"""Self-contact through a motion (`simulate(..., contact=True)`, `skin.motion_contact`): the IPC barrier
frame to frame keeps the forearm's skin out of the upper arm's as the elbow flexes to 150°, where the
motion without it keeps skinning's crossings; and `hitogata simulate --contact`."""

from __future__ import annotations

import numpy as np
import pytest

from hitogata import cli
from hitogata.dynamics.motion import Motion
from hitogata.simulation.run import JUMP_SPEED, contact_figures
from hitogata.skin.single_pose import elastic_dynamics
from hitogata.motion.scenario import load_scenario, shipped_scenarios
from hitogata.geometry import self_intersections, surface_integrity
from hitogata.measure.body_lines import body_lines
from hitogata.skeleton.kinematics import Pose
from hitogata.skin.contact import skin_contact
from hitogata.skin.fine_skin import body_fine_skinning
from hitogata.skin.motion_contact import simulate

RATE = 10.0  # frames/s: the shipped scenario's flexion, 40° at 0 s → 150° at 0.9 s, in frames up to 19° apart


@pytest.fixture(scope="module")
def flexion(female):
    """The whole default female body (the model `elastic_pose` shares) flexing the left elbow, without and
    with contact."""
    scenario = load_scenario(shipped_scenarios()["elbow_flexion_body"])
    calls: list[tuple[int, int]] = []
    runs = {contact: simulate(elastic_dynamics(female, n_modes=2), scenario.timeline, 0.9, RATE, contact=contact,
                              progress=(lambda done, total: calls.append((done, total))) if contact else None)
            for contact in (False, True)}
    return runs, calls


@pytest.mark.slow
def test_contact_holds_through_an_elbow_flexion(female, flexion):
    runs, calls = flexion
    faces = female.faces
    rest = set(map(tuple, self_intersections(female.vertices, faces).tolist()))
    test = skin_contact(runs[True].dynamics.poser)

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
    assert round(worst["largest_elastic_jump_speed_m_s"], 2) == 0.11 < JUMP_SPEED
    # left: the crease's forearm skin pressed against the upper arm folds 3 neighbouring triangle pairs over
    # at 150° (skin of one group nearer than BarrierSettings.same_apart at rest, which the barrier lets meet)
    assert (worst["folds_beyond_skinning"], worst["new_folds_time_s"]) == (3, 0.9)


@pytest.mark.slow
def test_the_elbow_crease_folds_through_the_motion(female, flexion):
    """The crease's skin is tied back towards skinning's fold frame by frame as a held pose's is
    (`skin.creases`): the line across the front of the elbow shortens as skinning shortens it, where the
    40 mm tissue mesh alone bows it out (the motion without contact)."""
    runs, _ = flexion
    fine = body_fine_skinning(female)
    line = body_lines(female, fine.fine.vertices, fine.fine.faces)["elbow_anterior"]
    rest = line.length(fine.fine.vertices)

    def change(motion: Motion, skins: np.ndarray) -> list[float]:
        """% change of the line's length on the fine skin, per frame."""
        return [round((line.length(fine.surface(Pose(motion.dynamics.poser.skeleton, motion.rotations[k:k + 1],
                                                     motion.translations[k:k + 1]), "dqs", skins[k].astype(float)))
                       / rest - 1) * 100, 1) for k in range(len(skins))]

    plain, held = runs[False], runs[True]
    elastic, resolved = change(plain, plain.skin), change(held, held.skin)
    # 40° → 150° at 0.9 s: from 0.5 s on, the crease closed, the line is shorter than the elastic body's
    assert all(r < e for r, e in list(zip(resolved, elastic))[5:])
    # to 0.3 %: the barrier's Newton steps end within its tolerance (0.5 mm), where round-off can move them. At
    # 150° -17.6 % (the elastic body -2.0 %, skinning -6.2 %; the held pose -23.0 %, reached from rest rather
    # than frame by frame)
    assert resolved == pytest.approx([0.0, -1.9, -7.1, -14.4, -18.5, -24.0, -22.1, -16.7, -17.8, -17.6], abs=0.3)


def test_simulate_takes_contact(capsys):
    """`hitogata simulate --contact` asks the run for contact (default off); a value given to it is one
    line, exit 2."""
    parse = cli.build_parser("simulate").parse_args
    assert parse(["simulate", "rectus_stretch", "--contact"]).contact is True
    assert parse(["simulate", "rectus_stretch"]).contact is False
    assert cli.main(["simulate", "rectus_stretch", "--contact=yes"]) == 2
    assert capsys.readouterr().err.splitlines() == [
        "hitogata: error: argument --contact: ignored explicit argument 'yes'"]
