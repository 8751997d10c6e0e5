"""The Python API answers a caller's mistake with one HitogataError line, as the command line does.

None where a body goes, units written as text where SI numbers go, NaN and
inf, a joint's common name, a simulation larger than memory, a mesh with NaN
vertices, a density no person has: each is refused where it enters, naming
the argument and what is allowed, before any work or file.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

import hitogata as hg
from hitogata.body import Body
from hitogata.dynamics.motion import simulate
from hitogata.dynamics.timeline import Keyframe, Timeline
from hitogata.errors import HitogataError, excerpt, one_line
from hitogata.export.meshfiles import write_mesh


def one_line_error(call) -> str:
    with pytest.raises(HitogataError) as err:
        call()
    message = str(err.value)
    assert "\n" not in message and len(message) <= 280, message
    return message


def test_none_for_a_body_is_named(female):
    assert one_line_error(lambda: hg.pose_body(None)).startswith("body 'NoneType': allowed a Body")
    assert one_line_error(lambda: hg.measure(None)).startswith("body 'NoneType': allowed a Body or a PosedBody")


def test_units_as_text_are_refused_with_what_the_api_takes(female):
    message = one_line_error(lambda: hg.pose_body(female, clinical={"shank_r.flexion": "60deg"}))
    assert message.startswith("clinical['shank_r.flexion'] = '60deg': allowed a finite number in radians")
    message = one_line_error(lambda: hg.pose_body(female, contractions={"biceps_brachii_l": float("nan")}))
    assert message.startswith("contractions['biceps_brachii_l'] = nan: allowed a finite number")
    message = one_line_error(lambda: hg.pose_body(female, clinical={"shoulder_l.flexion": "x"}))
    assert message.startswith("clinical['shoulder_l.flexion'] = 'x'")


def test_a_joints_common_name_points_to_the_skeletons(female):
    message = one_line_error(lambda: hg.pose_body(female, clinical={"knee_r.flexion": math.radians(60)}))
    assert message == "clinical['knee_r.flexion']: no joint angle of that name; did you mean shank_r.flexion " \
                      "(the skeleton's name)?"
    posed = hg.pose_body(female, clinical={"shank_r.flexion": math.radians(60)})  # the suggestion works
    assert np.isfinite(posed.vertices).all()


def test_the_shoulder_at_flexion_and_abduction_180_says_what_it_would_do(female):
    message = one_line_error(lambda: hg.pose_body(female, clinical={"shoulder_l.flexion": math.pi,
                                                                     "shoulder_l.abduction": math.pi}))
    assert message.startswith("shoulder_l.flexion 180° with shoulder_l.abduction 180°: the two turns past 90° undo "
                              "each other (the arm ends 0° from hanging)")


@pytest.mark.parametrize("time, value, said", [
    (float("nan"), 0.1, "keyframe 1: time nan"),
    (float("inf"), 0.1, "keyframe 1: time inf"),
    (0.5, float("nan"), "keyframe 1: angle 'shank_r.flexion' = nan"),
    (0.5, float("-inf"), "keyframe 1: angle 'shank_r.flexion' = -inf"),
    (0.5, "60deg", "keyframe 1: angle 'shank_r.flexion' = '60deg'"),
    (1e9, 0.1, "keyframe 1: time 1000000000.0; allowed a number of seconds 0..600"),
])
def test_a_timeline_refuses_nan_and_inf(time, value, said):
    message = one_line_error(lambda: Timeline.from_keyframes([Keyframe(time, {("angle", "shank_r.flexion"): value})]))
    assert message.startswith(said)


def test_a_simulation_beyond_its_limits_or_the_memory_is_refused_before_allocating():
    timeline = Timeline.from_keyframes([Keyframe(0.5, {("angle", "shank_r.flexion"): 0.5})])
    message = one_line_error(lambda: simulate(None, timeline, duration=1e9, rate=1e9))  # type: ignore[arg-type]
    assert message == ("duration 1000000000.0 s and rate 1000000000.0/s: allowed a duration up to 600 s and a rate "
                       "up to 240 frames/s")
    huge = SimpleNamespace(n_nodes=10**9, eigenvalues=np.zeros(40),
                           poser=SimpleNamespace(skeleton=SimpleNamespace(names=["part"] * 65)))
    message = one_line_error(lambda: simulate(huge, timeline, duration=600, rate=240))  # type: ignore[arg-type]
    assert message.startswith("duration 600 s at 240 frames/s, 1 substeps: needs ") and "GiB free" in message


def test_write_mesh_refuses_nan_vertices_and_writes_nothing(tmp_path):
    vertices = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [np.nan, 0, 0]])
    faces = np.array([[0, 1, 2]])
    message = one_line_error(lambda: write_mesh(tmp_path / "m.obj", vertices, faces))
    assert message == f"{tmp_path / 'm.obj'}: vertices of shape (4, 3), vertex 3 not finite; allowed (V, 3) finite numbers"
    message = one_line_error(lambda: write_mesh(tmp_path / "m.obj", vertices[:3], np.array([[0, 1, 7]])))
    assert message.endswith("allowed (F, 3) vertex indices 0..2")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("density", [-1000.0, float("nan"), 0.0, 5000.0, "heavy"])
def test_a_density_no_person_has_is_refused_where_it_enters(female, density):
    message = one_line_error(lambda: Body(female.params, female.all_vertices, density))  # type: ignore[arg-type]
    assert message.startswith("density ") and "allowed a whole-body density 900–1100 kg/m³" in message
    assert one_line_error(lambda: Body.from_measurements(sex="female", density=density)).startswith("density ")


def test_messages_quote_a_short_escaped_excerpt():
    assert excerpt("x" * 1000) == repr("x" * 40) + "… (1,000 characters)"
    assert excerpt("a\nb\x00") == "'a\\nb\\x00'"
    long = one_line("start " + "y" * 10_000_000 + "\nend")
    assert len(long) <= 280 and long.startswith("start yyy") and long.endswith("y end")
    assert len(str(HitogataError("z" * 100_000))) <= 280


def test_a_warning_is_said_once_as_one_line_without_source(capsys):
    import warnings

    from hitogata.errors import warnings_as_lines
    from hitogata.muscles.geometry import MuscleGeometryWarning

    with warnings.catch_warnings():
        warnings_as_lines()
        for _ in range(3):  # the same warning for every body of a run
            warnings.warn("a muscle's path crosses the bone", MuscleGeometryWarning, stacklevel=1)
        warnings.warn("another one", MuscleGeometryWarning, stacklevel=1)
    assert capsys.readouterr().err == ("hitogata: warning: a muscle's path crosses the bone\n"
                                       "hitogata: warning: another one\n")


def test_a_request_no_person_could_have_is_refused_before_the_search(monkeypatch):
    import hitogata.made_to_measure.solve as mtm

    monkeypatch.setattr(mtm, "_Problem", lambda *_, **__: pytest.fail("the search began"))
    message = one_line_error(lambda: mtm.body_to_measure("female", {"stature": 1.65, "chest": 0.80, "waist": 1.40,
                                                                     "hip": 0.85}))
    assert message == ("waist_girth 140.0 cm with hip_girth 85.0 cm: waist_girth 1.65 times the hip_girth; allowed "
                       "0.55–1.3 (beyond every adult's proportions)")
