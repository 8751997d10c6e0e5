"""Scenario files: units at the edge, one-line errors naming file and entry, keyframe interpolation."""

from pathlib import Path

import numpy as np
import pytest

from hitogata.motion.scenario import load_scenario, parse_scenario, shipped_scenarios
from hitogata.dynamics.timeline import Channel, Keyframe, Timeline
from hitogata.errors import HitogataError

GOOD = """
title = "t"
[body]
sex = "male"
age = 40
stature = "178cm"
mass = "75kg"
[model]
extent = "body"
element_size = "5cm"
damping = [{ frequency = "2Hz", ratio = 0.2 }, { frequency = "10Hz", ratio = "15%" }]
[time]
duration = "1500ms"
rate = 25
[[keyframe]]
time = 0
[[keyframe]]
time = "0.5s"
interpolation = "linear"
contractions = { biceps_brachii_l = "10%" }
clinical = { "forearm_r.flexion" = "90deg" }
angles = { "thigh_l.flexion" = 20 }
[output]
files = ["glb", "png"]
snapshots = ["0.5s", 1]
"""


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "s.toml"
    path.write_text(text)
    return path


def test_a_scenario_in_person_units_becomes_si(tmp_path):
    s = load_scenario(write(tmp_path, GOOD))
    assert (s.body.sex, s.body.age, s.body.stature, s.body.mass) == ("male", 40.0, pytest.approx(1.78), 75.0)
    assert s.model.extent == "body" and s.model.element_size == pytest.approx(50.0)  # mm
    assert s.model.damping_ratios == ((2.0, 0.2), (10.0, pytest.approx(0.15)))
    assert s.duration == pytest.approx(1.5) and s.rate == 25.0 and s.substeps == 1
    assert s.output.files == ("glb", "png") and s.output.snapshots == (0.5, 1.0)
    sampled = s.timeline.sample(np.array([0.0, 0.25, 0.5, 1.0]))
    assert sampled["contraction"]["biceps_brachii_l"] == pytest.approx([0.0, 0.05, 0.1, 0.1])
    assert sampled["clinical"]["forearm_r.flexion"][-1] == pytest.approx(np.pi / 2)
    assert sampled["angle"]["thigh_l.flexion"][2] == pytest.approx(np.radians(20))  # bare number: degrees


@pytest.mark.parametrize("edit, message", [
    (("[body]\nsex = \"male\"", "[body]\nsex = \"robot\""), "s.toml: [body].sex: 'robot'"),
    (("mass = \"75kg\"", "mass = \"75\""), "s.toml: [body].mass: '75' is not a mass"),
    (("mass = \"75kg\"\n", ""), "s.toml: [body].mass: give stature and mass together"),
    (("extent = \"body\"", "extent = \"leg\""), "s.toml: [model].extent: 'leg'; allowed trunk, body"),
    (("element_size = \"5cm\"", "element_size = \"1m\""), "s.toml: [model].element_size: '1m' is out of range"),
    (("ratio = 0.2", "ratio = -1"), "s.toml: [model].damping[0].ratio: -1 is out of range"),
    (("time = \"0.5s\"", "time = \"0s\""), "s.toml: [[keyframe]] 2.time: '0s' is not after the previous"),
    (("interpolation = \"linear\"", "interpolation = \"cubic\""), "s.toml: [[keyframe]] 2.interpolation: 'cubic'"),
    (("\"90deg\"", "\"90 furlongs\""), "s.toml: [[keyframe]] 2.clinical.forearm_r.flexion: '90 furlongs'"),
    (("rate = 25", "rate = 25\nspeed = 2"), "s.toml: [time]: unknown key 'speed'"),
    (("files = [\"glb\", \"png\"]", "files = [\"mp4\"]"), "s.toml: [output].files: ['mp4']"),
    (("snapshots = [\"0.5s\", 1]", "snapshots = [\"9s\"]"), "s.toml: [output].snapshots.0: '9s' is out of range"),
])
def test_bad_entries_give_one_line_naming_file_and_entry(tmp_path, edit, message):
    old, new = edit
    assert old in GOOD
    with pytest.raises(HitogataError) as err:
        load_scenario(write(tmp_path, GOOD.replace(old, new, 1)))
    text = str(err.value)
    assert "\n" not in text and message in text, text


def test_broken_toml_and_missing_file(tmp_path):
    with pytest.raises(HitogataError, match=r"s.toml: not valid TOML"):
        load_scenario(write(tmp_path, "[body\n"))
    with pytest.raises(HitogataError, match="no such file"):
        load_scenario(tmp_path / "none.toml")
    with pytest.raises(HitogataError, match=r"\[\[keyframe\]\]: at least one keyframe"):
        parse_scenario({}, "x.toml")


def test_shipped_scenarios_load():
    shipped = shipped_scenarios()
    assert {"rectus_stretch", "trunk_flexion_arms_raised", "elbow_flexion_body"} <= set(shipped)
    for path in shipped.values():
        s = load_scenario(path)
        assert s.timeline.channels and s.duration > s.timeline.end


def test_smoothstep_starts_and_stops_at_rest_and_linear_keeps_speed():
    c = Channel("contraction", "m", (0.0, 1.0, 3.0), (0.0, 1.0, 0.0), ("linear", "smoothstep", "linear"))
    t = np.array([0.0, 0.5, 1.0, 2.0, 3.0, 4.0])
    assert c(t) == pytest.approx([0.0, 0.5, 1.0, 0.5, 0.0, 0.0])  # held after the last keyframe
    h = 1e-6
    for where in (0.0 + h, 1.0 - h):  # smoothstep (0 -> 1): zero velocity at both ends
        smooth = Channel("contraction", "m", (0.0, 1.0), (0.0, 1.0), ("linear", "smoothstep"))
        assert abs(smooth(np.array(where + h)) - smooth(np.array(where - h))) / (2 * h) < 1e-3
    assert c(np.array(1.5)) == pytest.approx(0.75)  # the linear segment 1 -> 0 over 1..3 s, a quarter in


def test_a_channel_starts_at_rest_before_its_first_keyframe():
    tl = Timeline.from_keyframes([Keyframe(0.0, {}), Keyframe(1.0, {("angle", "a.b"): 2.0}, "linear")])
    assert tl.sample(np.array([0.0, 0.5, 1.0]))["angle"]["a.b"] == pytest.approx([0.0, 1.0, 2.0])
    with pytest.raises(HitogataError, match="strictly increasing"):
        Timeline.from_keyframes([Keyframe(1.0, {}), Keyframe(1.0, {})])


def test_a_clinical_channel_starts_from_the_rest_pose_not_the_anatomical_zero():
    """The elbow rests ~40° flexed: a clinical channel first named later starts there, at t = 0."""
    tl = Timeline.from_keyframes([Keyframe(0.0, {}), Keyframe(1.0, {("clinical", "forearm_l.flexion"): 2.0}, "linear")])
    rest = {("clinical", "forearm_l.flexion"): 0.7}
    assert tl.sample(np.array([0.0, 0.5, 1.0]), rest)["clinical"]["forearm_l.flexion"] == pytest.approx([0.7, 1.35, 2.0])
    named = Timeline.from_keyframes([Keyframe(0.0, {("clinical", "forearm_l.flexion"): 0.0}),
                                     Keyframe(1.0, {("clinical", "forearm_l.flexion"): 2.0}, "linear")])
    assert named.sample(np.array([0.0]), rest)["clinical"]["forearm_l.flexion"] == pytest.approx([0.0])  # said so
