"""The scenario player's sequences, loaders and clock (no server)."""

import numpy as np
import pytest

from hitogata.errors import HitogataError
from hitogata.posing import poser_for
from hitogata.viewer.frame import sequence_frame
from hitogata.viewer.player import FRAME_RATE, RESULT_FILE, Clock, Sequence, load_sequence


@pytest.fixture()
def poser(female):
    return poser_for(female)


def write_sequence(path, poser, frames=4, with_angles=True):
    q = np.zeros((frames, poser.skeleton.n_dofs))
    q[:, poser.skeleton.dof_index("forearm_r.flexion")] = np.linspace(0.0, 1.0, frames)
    arrays = {"times": np.linspace(0.0, 0.3, frames), "vertices": poser.pose_many(q)}
    if with_angles:
        arrays["angles"] = q
    np.savez(path, **arrays)
    return q


def test_npz_file_and_results_folder_load_alike(tmp_path, poser):
    q = write_sequence(tmp_path / RESULT_FILE, poser)
    for path in (tmp_path / RESULT_FILE, tmp_path):
        seq = load_sequence(path, poser)
        assert seq.vertices.shape == (4, len(poser.body.vertices), 3)
        np.testing.assert_allclose(seq.angles, q)
    frame = sequence_frame(poser, seq, 3)
    assert frame.pose is not None and frame.bones().shape == (poser.skeleton.joints.shape[0], 2, 3)
    assert not np.allclose(frame.rig_joints, poser.body.rig.heads)  # the elbow moved the wrist's joints


def test_a_sequence_without_angles_has_no_skeleton_and_rest_joints(tmp_path, poser):
    write_sequence(tmp_path / "s.npz", poser, with_angles=False)
    frame = sequence_frame(poser, load_sequence(tmp_path / "s.npz", poser), 2)
    assert frame.pose is None and frame.bones() is None
    np.testing.assert_array_equal(frame.rig_joints, poser.body.rig.heads)


def test_keyframes_are_posed_and_interpolated(tmp_path, poser):
    path = tmp_path / "wave.toml"
    path.write_text(
        "[[keyframe]]\ntime = 0.0\n"
        "[[keyframe]]\ntime = 1.0\ncontractions = { biceps_brachii_r = 0.2 }\n"
        '[[keyframe]]\ntime = 2.0\nclinical = { "thigh_r.flexion" = 45.0 }\n'
    )
    seq = load_sequence(path, poser)
    assert len(seq.times) == int(2.0 * FRAME_RATE) + 1
    elbow = seq.angles[:, poser.skeleton.dof_index("forearm_r.flexion")]
    end = poser.angles(contractions={"biceps_brachii_r": 0.2})[poser.skeleton.dof_index("forearm_r.flexion")]
    assert elbow[0] == 0.0 and elbow[int(FRAME_RATE)] == pytest.approx(end) and elbow[int(FRAME_RATE / 2)] == pytest.approx(end / 2)
    hip = seq.angles[-1, poser.skeleton.dof_index("thigh_r.flexion")] + poser.skeleton.rest[poser.skeleton.dof_index("thigh_r.flexion")]
    assert np.degrees(hip) == pytest.approx(45.0)
    np.testing.assert_allclose(seq.vertices[0], poser.body.vertices, atol=1e-5)


@pytest.mark.parametrize(
    ("content", "message"),
    [
        ("[[keyframe]]\ntime = 0.0\n", "two or more"),
        ("[scenario]\ntitle = 'a dynamics scenario'\n", r"no \[\[keyframe\]\] tables; allowed pose keyframes or a scenario"),
        ("[[keyframe]]\ntime = 1.0\n[[keyframe]]\ntime = 0.5\n", "increasing"),
        ("[[keyframe]]\ntime = 0.0\n[[keyframe]]\ntime = 1.0\ncontractions = { nosuch = 0.1 }\n", "keyframe 2.*nosuch"),
        ("[[keyframe]]\ntime = 0.0\n[[keyframe]]\ntime = 1.0\ncontractions = { quadriceps_r = 9.0 }\n", "keyframe 2.*quadriceps_r"),
        ("[[keyframe]]\ntime = 0.0\n[[keyframe]]\ntime = 1.0\ncontractions = { quadriceps_r = 'a' }\n", "finite number"),
        ("[[keyframe]]\ntime = 0.0\nspeed = 2\n[[keyframe]]\ntime = 1.0\n", "unknown key 'speed'"),
        ("[[keyframe]\n", "not valid TOML"),
    ],
)
def test_broken_keyframe_files_are_one_line_errors(tmp_path, poser, content, message):
    path = tmp_path / "broken.toml"
    path.write_text(content)
    with pytest.raises(HitogataError, match=message) as err:
        load_sequence(path, poser)
    assert "\n" not in str(err.value) and "broken.toml" in str(err.value)


def test_broken_sequence_files_are_one_line_errors(tmp_path, poser):
    cases = {
        "garbage.npz": (lambda p: p.write_bytes(b"not a zip"), "not a readable .npz"),
        "novertices.npz": (lambda p: np.savez(p, times=np.zeros(2)), "no array 'vertices'"),
        "wrongshape.npz": (lambda p: np.savez(p, times=np.arange(2.0), vertices=np.zeros((2, 10, 3))), "vertices of shape"),
        "backwards.npz": (lambda p: np.savez(p, times=np.array([1.0, 0.0]), vertices=np.zeros((2, len(poser.body.vertices), 3))), "increasing"),
        "nan.npz": (lambda p: np.savez(p, times=np.arange(2.0), vertices=np.full((2, len(poser.body.vertices), 3), np.nan)), "not finite"),
        "other.obj": (lambda p: p.write_text("v 0 0 0"), "unknown kind of file"),
    }
    for name, (make, message) in cases.items():
        make(tmp_path / name)
        with pytest.raises(HitogataError, match=message):
            load_sequence(tmp_path / name, poser)
    with pytest.raises(HitogataError, match="no such file"):
        load_sequence(tmp_path / "missing.npz", poser)
    with pytest.raises(HitogataError, match="a results folder holds one"):
        load_sequence(tmp_path, poser)  # a folder without the results file


def test_frame_at_shows_the_frame_that_has_begun():
    seq = Sequence("s", np.array([0.0, 0.5, 1.0]), np.zeros((3, 1, 3), dtype=np.float32))
    assert [seq.frame_at(t) for t in (-1.0, 0.0, 0.49, 0.5, 0.99, 1.0, 7.0)] == [0, 0, 0, 1, 1, 2, 2]


def test_clock_plays_pauses_scrubs_and_stops_at_the_end():
    clock = Clock(0.0, 1.0)
    assert clock.advance(0.5) == 0.0  # paused at first
    clock.play()
    assert clock.advance(0.4) == pytest.approx(0.4)
    clock.pause()
    assert clock.advance(0.4) == pytest.approx(0.4)
    clock.scrub(0.9)
    clock.play()
    assert clock.advance(0.5) == 1.0 and not clock.playing
    clock.play()  # from the start again
    assert clock.time == 0.0 and clock.playing
    clock.scrub(-3.0)
    assert clock.time == 0.0


TINY_SCENARIO = """
title = "tiny"
[model]
element_size = "60mm"
modes = 6
[time]
duration = "0.3s"
rate = 10
[timeline]
on_limit = "clamp"
[[keyframe]]
time = 0
[[keyframe]]
time = "0.2s"
contractions = { rectus_abdominis_l = "-5%" }
"""


def test_a_dynamics_scenario_is_simulated_on_the_viewers_body(tmp_path, poser):
    path = tmp_path / "tiny.toml"
    path.write_text(TINY_SCENARIO)
    seq = load_sequence(path, poser)
    assert len(seq.times) == 4 and seq.times[-1] == pytest.approx(0.3)
    assert seq.vertices.shape == (4, len(poser.body.vertices), 3)
    assert np.abs(seq.vertices[-1] - poser.body.vertices).max() > 1e-3  # the trunk moved
    assert np.abs(seq.vertices[0] - poser.body.vertices).max() < 1e-6  # from rest
