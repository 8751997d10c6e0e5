"""The viewer's library side, without a server: posing state, slider ranges, groups, colours, tissue, export."""

import re
import time

import numpy as np
import pytest

from gltf_validator import needs_validator, validate_gltf
from waiting import PATIENCE
from hitogata.errors import HitogataError
from hitogata.export.glb_read import read_glb_skin
from hitogata.viewer.colouring import LIMIT_PERCENT, StrainColouring
from hitogata.viewer.export import pose_glb
from hitogata.viewer.frame import posed_frame
from hitogata.viewer.groups import OTHER, muscle_groups, region_of, slider_label
from hitogata.viewer.state import SLIDER_STEP, PoseState
from hitogata.viewer.worker import Worker


@pytest.fixture()
def state(female):
    return PoseState(female)


def test_every_muscle_has_a_slider_in_one_region_folder(state):
    groups = muscle_groups(state.muscles)
    names = [n for members in groups.values() for n in members]
    assert sorted(names) == sorted(state.muscles.names) and len(names) == 114
    assert OTHER not in groups
    assert list(groups)[:3] == ["Trunk", "Neck and jaw", "Left shoulder"]
    assert "biceps_brachii_r" in groups["Right elbow and forearm"]
    assert region_of("my_new_part") == OTHER


def test_slider_labels_drop_the_side_only_where_the_folder_says_it():
    assert slider_label("biceps_brachii_l", "Left elbow and forearm") == "biceps brachii"
    assert slider_label("rectus_abdominis_r", "Trunk") == "rectus abdominis (right)"


def test_slider_ranges_span_each_joint_range_and_both_ends_pose(state):
    ranges = state.ranges
    assert np.all(ranges.low <= 0.0) and np.all(ranges.high >= 0.0)
    assert np.all(ranges.high - ranges.low > 5.0)  # percent: every slider moves its joint visibly
    refused = set()
    for k, name in enumerate(state.muscles.names):
        state.reset()  # each slider alone: two at their ends may break a combined limit
        for end in (ranges.low[k], ranges.high[k]):
            try:
                state.set_contraction(name, end / 100.0)  # never beyond the joint's range
            except HitogataError as err:  # a hip adducted 30° with the other leg at rest: through it
                assert re.match(r"hips.abduction \(both legs\) = -2[34].\d° clinical", str(err))
                refused.add(name)
    assert refused == {f"{m}_{s}" for m in ("adductor_magnus", "gluteus_medius") for s in "lr"}
    # rounded inwards to the step: one step further is refused
    k = state.muscles.index("biceps_brachii_r")
    with pytest.raises(HitogataError, match="biceps_brachii_r"):
        state.set_contraction("biceps_brachii_r", (ranges.high[k] + 2 * SLIDER_STEP) / 100.0)


def test_a_moved_muscle_takes_over_its_joints_and_the_others_follow(state):
    state.set_contraction("biceps_brachii_r", 0.2)
    elbow = state.posed.angle("forearm_r.flexion")
    assert elbow > 0.3
    values = state.slider_values()
    assert values["biceps_brachii_r"] == pytest.approx(20.0)
    assert values["triceps_brachii_r"] < -1.0  # the antagonist is stretched
    assert values["biceps_brachii_l"] == 0.0
    state.set_contraction("triceps_brachii_r", 0.0)  # the antagonist takes the elbow back to rest
    assert state.drivers == {"triceps_brachii_r": 0.0}
    assert state.posed.angle("forearm_r.flexion") == pytest.approx(0.0, abs=1e-9)
    state.set_contraction("rectus_abdominis_l", 0.1)  # the spine: the bilateral twin follows
    assert state.slider_values()["rectus_abdominis_r"] == pytest.approx(10.0)
    assert set(state.drivers) == {"triceps_brachii_r", "rectus_abdominis_l"}


def test_a_refused_contraction_leaves_the_pose_unchanged(state):
    state.set_contraction("quadriceps_r", 0.05)
    before = state.posed
    with pytest.raises(HitogataError):
        state.set_contraction("quadriceps_r", 5.0)
    assert state.posed is before and state.drivers == {"quadriceps_r": 0.05}


def test_reset_returns_to_the_rest_surface(state, female):
    state.set_contraction("deltoid_l", 0.1)
    assert not np.allclose(state.posed.vertices, female.vertices)
    state.reset()
    np.testing.assert_allclose(state.posed.vertices, female.vertices, atol=1e-12)
    assert all(v == 0.0 for v in state.slider_values().values())


def test_a_new_body_keeps_the_joint_angles(state, male):
    state.set_contraction("biceps_brachii_l", 0.15)
    angles = state.posed.angles.copy()
    state.set_body(male)
    np.testing.assert_allclose(state.posed.angles, angles, atol=1e-9)
    assert state.posed.vertices.shape == male.vertices.shape
    assert state.drivers["biceps_brachii_l"] == pytest.approx(state.contractions()[state.muscles.index("biceps_brachii_l")])


def test_successive_slider_moves_each_pose_and_skin(state):
    """Each move re-poses and re-skins; its time per move is benchmarks/bench_viewer.py's figure."""
    state.set_contraction("biceps_brachii_r", 0.0)
    elbow = []
    for k in range(5):
        state.set_contraction("biceps_brachii_r", 0.05 * k)
        elbow.append(state.posed.angle("forearm_r.flexion"))
    assert np.all(np.diff(elbow) > 0)  # each step bends the elbow further


def test_strain_colours_are_neutral_at_rest_and_red_where_stretched(state, female):
    colouring = StrainColouring(female.vertices, female.faces)
    rest = colouring.colours(female.vertices)
    assert rest.shape == (len(female.vertices), 3) and rest.dtype == np.uint8
    assert np.ptp(rest.astype(int), axis=0).max() <= 2  # one colour: no strain anywhere
    posed = state.set_contraction("biceps_brachii_r", 0.3)
    strain = colouring.vertex_strain(posed.vertices)
    assert strain.max() > 10.0 and np.all(np.isfinite(strain))
    hot = colouring.colours(posed.vertices)[np.argmax(strain)]
    assert hot[0] > hot[2]  # red over blue
    assert LIMIT_PERCENT > 0


def test_pose_glb_carries_the_posed_surface_and_rig(tmp_path, state, female):
    posed = state.set_contraction("biceps_brachii_r", 0.2)
    path = tmp_path / "pose.glb"
    frame = posed_frame(posed)
    path.write_bytes(pose_glb(female, frame))
    skin = read_glb_skin(path)
    np.testing.assert_allclose(skin.vertices, posed.vertices, atol=1e-5)
    np.testing.assert_allclose(skin.joint_positions, frame.rig_joints, atol=1e-5)
    assert skin.joint_names == female.rig.names and skin.extras["posed"] is True


@needs_validator
def test_pose_glb_passes_the_khronos_validator(tmp_path, state, female):
    posed = state.set_contraction("iliopsoas_l", 0.1)
    path = tmp_path / "pose.glb"
    path.write_bytes(pose_glb(female, posed_frame(posed)))
    report, returncode = validate_gltf(path)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    assert returncode == 0


def test_worker_coalesces_requests_and_survives_a_failing_run():
    runs, errors = [], []

    def job():
        runs.append(1)
        time.sleep(0.05)
        if len(runs) == 1:
            raise RuntimeError("boom")

    worker = Worker(job, "test", errors.append)
    try:
        for _ in range(10):
            worker.request()
        assert worker.wait_idle(PATIENCE)
        assert 1 <= len(runs) <= 3
        assert errors == ["test: boom"]
        worker.request()
        assert worker.wait_idle(PATIENCE) and len(runs) >= 2
    finally:
        worker.stop()

