"""Dynamic ease: zero on a rigid motion, the across-back widens and the across-front narrows on reach-forward."""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from hitogata.cli import main
from hitogata.motion.scenario import load_scenario, shipped_scenarios
from hitogata.garment.ease import HEIGHTS, NAMES, MotionEase, ease_csv, ease_json, motion_ease, overall
from hitogata.garment.ease_plot import ease_plot
from hitogata.measure import measure
from hitogata.motion.clip import MotionClip, scenario_clip
from hitogata.posing import poser_for
from hitogata.measure.landmarks import body_landmarks


def rigid_clip(n_dofs: int) -> MotionClip:
    turns = Rotation.from_euler("yxz", [[0, 0, 0], [40, 10, 0], [-90, -15, 20]], degrees=True).as_matrix()
    root = np.tile(np.eye(4), (3, 1, 1))
    root[:, :3, :3] = turns
    root[:, :3, 3] = [[0, 0, 0], [0.3, 0.1, -0.2], [-1.0, 0.5, 2.0]]
    return MotionClip(np.array([0.0, 0.5, 1.0]), np.zeros((3, n_dofs)), root)


@pytest.mark.parametrize("sex", ["female", "male"])
def test_a_rigid_motion_changes_no_girth_or_length(request, sex):
    body = request.getfixturevalue(sex)
    ease = motion_ease(body, "rigid", rigid_clip(poser_for(body).skeleton.n_dofs), rate=2.0)
    assert len(ease.times) == 3
    kept = [k for k, n in enumerate(NAMES) if n not in HEIGHTS]
    assert np.abs(ease.change[:, kept]).max() < 1e-5  # metres (a geodesic may settle on a near-equal path: 7 µm)


@pytest.mark.parametrize("sex, back, front", [("female", 6.4, -5.6), ("male", 7.9, -7.4)])
def test_reach_forward_widens_the_back_and_narrows_the_front(request, sex, back, front):
    body = request.getfixturevalue(sex)
    clip = scenario_clip(load_scenario(shipped_scenarios()["mobility_reach_forward"]), poser_for(body))
    ease = motion_ease(body, "reach_forward", clip, rate=2.5)
    rows = {r["measurement"]: r for r in ease.largest()}
    assert rows["across_back_width"]["increase_cm"] == pytest.approx(back, abs=0.3)
    assert rows["across_back_width"]["decrease_cm"] > -0.1
    assert rows["across_front_width"]["decrease_cm"] == pytest.approx(front, abs=0.3)
    assert rows["across_front_width"]["increase_cm"] < 0.1
    assert rows["shoulder_width"]["increase_cm"] > 2  # over the back, between the acromia (they ride the girdle)
    table = ease_csv([ease])
    assert table.splitlines()[0].startswith("motion,measurement,standing_cm,increase_cm")
    assert len(table.splitlines()) == 1 + 2 * len(NAMES)
    assert '"all"' in ease_json([ease]) and overall([ease])[NAMES.index("chest_girth")]["increase_in"] == "reach_forward"
    assert ease_plot([ease]).startswith(b"\x89PNG")


def test_armpit_folds_lie_behind_and_before_the_sides(female, male):
    for body in (female, male):
        marks, v = body_landmarks(body), body.vertices
        assert marks.fold_back_right.at(v)[0] < -0.1 < 0.1 < marks.fold_back_left.at(v)[0]
        assert marks.fold_back_right.at(v)[2] < marks.fold_front_right.at(v)[2]
        assert 0.30 < measure(body).across_back_width < 0.45


def test_ease_command_checks_motions_before_work(tmp_path, capsys):
    assert main(["ease", "--motions", "reach_forward,cartwheel", "--out", str(tmp_path / "e")]) == 2
    assert "--motions: 'cartwheel'; allowed a scenario file (.toml) or arms_crossed" in capsys.readouterr().err
    assert not (tmp_path / "e").exists()


def test_pressure_through_sitting(male):
    from hitogata.garment import Fabric, Garment
    from hitogata.garment.pressure_motion import pressure_csv, pressure_series

    clip = scenario_clip(load_scenario(shipped_scenarios()["mobility_sit"]), poser_for(male))
    times, levels = pressure_series(male, Garment(ease=-0.15), Fabric.linear(400.0), clip, rate=2.5)
    assert np.ptp(levels["ankle"][:, 1]) < 1e-6  # the ankle does not move
    knee = levels["knee"]
    assert knee[0, 0] == pytest.approx(0.15 / 0.85) and knee[:, 0].max() > knee[0, 0] + 0.1
    assert int(np.argmax(knee[:, 2])) not in (0, len(times) - 1)  # the peak is mid-motion, when seated
    assert pressure_csv({"sit": (times, levels)}).count("\n") == 1 + len(times) * 6


def test_ease_command_checks_the_garment_before_work(tmp_path, capsys):
    assert main(["ease", "--garment-ease=-15%", "--out", str(tmp_path / "e")]) == 2
    assert "--garment-ease and --fabric: give both" in capsys.readouterr().err
    assert main(["ease", "--garment-ease=-15%", "--fabric", "400N/mm", "--out", str(tmp_path / "e")]) == 2
    assert "--fabric modulus '400N/mm'" in capsys.readouterr().err
    assert not (tmp_path / "e").exists()


def test_ease_command_checks_the_surface_before_work(tmp_path, capsys):
    assert main(["ease", "--surface", "elastic", "--skinning", "lbs", "--out", str(tmp_path / "e")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["hitogata: error: --surface elastic: the elastic body stands on dual-quaternion skinning; "
                   "drop --skinning lbs"]
    assert main(["fit-report", "--surface", "elastic", "--skinning", "lbs", "--out", str(tmp_path / "r")]) == 2
    assert "--surface elastic: the elastic body stands on dual-quaternion skinning" in capsys.readouterr().err
    assert not (tmp_path / "e").exists() and not (tmp_path / "r").exists()


def test_heights_are_undefined_in_a_motion_never_a_number(female):
    """An inside leg while touching the toes has no meaning: the tables say so instead of giving -72 cm."""
    clip = scenario_clip(load_scenario(shipped_scenarios()["mobility_toe_touch"]), poser_for(female))
    ease = motion_ease(female, "toe_touch", clip, rate=1.0)
    for row in [*ease.largest(), *overall([ease])]:
        if row["measurement"] in HEIGHTS:
            assert row["increase_cm"] is None and row["decrease_cm"] is None and "standing" in row["undefined"]
        else:
            assert row["increase_cm"] is not None and row["decrease_cm"] is not None
    lines = [line for line in ease_csv([ease]).splitlines() if ",inside_leg," in line]
    assert len(lines) == 2 and all(",undefined," in line for line in lines)
    doc = json.loads(ease_json([ease]))
    k = doc["measurements"].index("inside_leg")
    assert all(row[k] is None for row in doc["motions"]["toe_touch"]["values_cm"])


def test_a_girth_undefined_in_some_frames_or_all_says_so(female):
    """A girth undefined in some frames (the knee girth at a deep squat's bottom) gives the figure over the
    others and says in how many it had none; undefined in every frame it is undefined, with the reason."""
    knee = NAMES.index("knee_girth")
    standing = np.full(len(NAMES), 0.4)
    values = np.tile(standing, (4, 1))
    values[:, knee] = [0.4, 0.43, np.nan, 0.41]
    partly = MotionEase("squat", np.array([0.0, 0.5, 1.0, 1.5]), values, standing)
    values = values.copy()
    values[:, knee] = np.nan
    wholly = MotionEase("kneel", np.array([0.0, 0.5, 1.0, 1.5]), values, standing)
    rows = {(r["motion"], r["measurement"]): r for r in [*partly.largest(), *wholly.largest(), *overall([partly, wholly])]}
    part, whole, both = rows["squat", "knee_girth"], rows["kneel", "knee_girth"], rows["all", "knee_girth"]
    assert part["increase_cm"] == pytest.approx(3.0) and part["increase_at_s"] == 0.5
    assert part["undefined"].startswith("in 1 of 4 frames (1 s") and "thigh and the calf" in part["undefined"]
    assert whole["increase_cm"] is None and whole["undefined"].startswith("in every frame: the knee girth")
    assert both["increase_cm"] == pytest.approx(3.0) and both["increase_in"] == "squat"
    assert "squat: in 1 of 4" in both["undefined"] and "kneel: in every frame" in both["undefined"]
    assert "undefined" not in rows["all", "calf_girth"]
    table = ease_csv([partly, wholly]).splitlines()
    assert table[0].endswith(",undefined_because")
    kneel = next(line for line in table if line.startswith("kneel,knee_girth,"))
    assert kneel.startswith("kneel,knee_girth,40,undefined,undefined,undefined,") and "nan" not in "".join(table)
    doc = json.loads(ease_json([partly, wholly]))  # strict JSON: no NaN
    assert doc["motions"]["squat"]["values_cm"][2][knee] is None and "knee_girth" in doc["undefined"]
