"""The apparel answers on the elastic whole body (`garment.ease.elastic_surface`, `hitogata ease --surface elastic`):
each frame held with its skin's self-contact resolved, against the skinned surface."""

from __future__ import annotations

import json

import numpy as np
import pytest

import hitogata.commands.ease as ease_command
import hitogata.skin.single_pose as single_pose
from hitogata.cli import main
from hitogata.motion.scenario import load_scenario, shipped_scenarios
from hitogata.garment.ease import NAMES, elastic_surface, motion_ease, sampled_frames, skinned_surface
from hitogata.garment.fit import fit_answers
from hitogata.motion.clip import scenario_clip
from hitogata.posing import poser_for
from test_garment_ease import rigid_clip

# the deep squat sampled at 2 frames/s, largest increase over standing (cm): skinned, then elastic with contact.
# With the skin's contact resolved the calf (pressed against the thigh) and the waist (the belly pressed by the
# thighs) grow by about 4 cm, where skinning gives 0. The knee girth is undefined at the squat's bottom on both
# surfaces: its plane (the bisector of femur and tibia) runs along the thigh and the calf there
# (`measure.measurements.knee_along_limbs`; a tape round them read +15.7 / +14.5 cm skinned), so its figures
# are those of the other frames, and the tables say so.
SQUAT = {
    "female": {"calf_girth": (0.0, 3.7), "waist_girth": (0.0, 4.0)},
    "male": {"calf_girth": (0.0, 4.5), "waist_girth": (0.0, 4.1)},
}


def squat(body):
    return scenario_clip(load_scenario(shipped_scenarios()["mobility_deep_squat"]), poser_for(body))


@pytest.mark.parametrize("sex", ["female", "male"])
def test_the_deep_squat_on_the_elastic_body(request, sex):
    body = request.getfixturevalue(sex)
    clip = squat(body)
    rows, knee = {}, []
    for surface in (skinned_surface(body), elastic_surface(body)):
        ease = motion_ease(body, "deep_squat", clip, surface, rate=2.0)
        for row in ease.largest():
            rows.setdefault(row["measurement"], []).append(row["increase_cm"])
        knee.append((ease.values[:, NAMES.index("knee_girth")], ease.times,
                     next(r for r in ease.largest() if r["measurement"] == "knee_girth")))
    for values, times, row in knee:  # undefined at the bottom (1.5 and 2 s: knee 130°), defined standing
        assert np.isnan(values[np.isin(times, (1.5, 2.0))]).all() and np.isfinite(values[times == 0.0]).all()
        assert "thigh and the calf" in row["undefined"] and row["increase_cm"] is not None
    # skinned: to 0.05 cm (no contact, the same on every machine); elastic: to 1 cm of the 1-10 cm the contact
    # adds, as the tape round the folded knee, calf and belly passes skin the barrier holds apart at its
    # Newton tolerance (1 mm), where another machine's round-off holds other pairs
    assert {name: rows[name][0] for name in SQUAT[sex]} == {
        name: pytest.approx(values[0], abs=0.05) for name, values in SQUAT[sex].items()}
    assert {name: rows[name][1] for name in SQUAT[sex]} == {
        name: pytest.approx(values[1], abs=1.0) for name, values in SQUAT[sex].items()}
    assert rows["calf_girth"][1] > rows["calf_girth"][0] and rows["waist_girth"][1] > rows["waist_girth"][0]


def test_a_rigid_motion_moves_the_elastic_skin_as_the_skinned(female):
    clip = rigid_clip(poser_for(female).skeleton.n_dofs)  # at rest, turned and moved about
    elastic = elastic_surface(female)(clip.angles, clip.root)
    skinned = skinned_surface(female)(clip.angles, clip.root)
    assert np.abs(elastic - skinned).max() < 1e-6  # m: at rest the elastic skin is the rest skin


def test_each_frame_is_held_once(female, monkeypatch):
    """Ease, stretch and the peak frames ask for the same frames: each distinct posture is solved once."""
    solved = []
    pose = single_pose.elastic_pose
    monkeypatch.setattr(single_pose, "elastic_pose", lambda *a, **k: solved.append(1) or pose(*a, **k))
    clip = squat(female)
    answers = fit_answers(female, {"deep_squat": clip}, elastic_surface(female), 1.0)
    distinct = np.unique(clip.angles[sampled_frames(clip, 1.0)], axis=0)
    assert len(solved) == len(distinct) == 5  # 0, 1, 2, 3 s and the last frame, each asked for by ease and stretch
    assert [s.motion for s in answers.stretch] == ["deep_squat"]


def test_ease_command_on_the_elastic_body(female, monkeypatch, tmp_path, capsys):
    monkeypatch.setattr(ease_command, "body_from_args", lambda args: female)  # its whole-body model built once here
    out = tmp_path / "ease"
    assert main(["ease", "--surface", "elastic", "--motions", "squat", "--rate", "1", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "elastic whole body: 5 frames to hold" in printed
    knee = next(r for r in json.loads((out / "ease.json").read_text())["motions"]["deep_squat"]["largest"]
                if r["measurement"] == "knee_girth")
    clip = squat(female)
    row = next(r for r in motion_ease(female, "deep_squat", clip, elastic_surface(female), rate=1.0).largest()
               if r["measurement"] == "knee_girth")
    assert knee["increase_cm"] == pytest.approx(row["increase_cm"], abs=1e-6)
    assert sorted(p.name for p in out.iterdir()) == ["ease.csv", "ease.json", "ease.png", "stretch.csv"]
