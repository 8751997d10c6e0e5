"""A body made to measure (issue 15, point 2): bodies rebuilt from their own measurements, what
cannot be met, the measure modifiers, and `hitogata body` with measurements or a size chart."""

from __future__ import annotations

import math
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from hitogata import cli
from hitogata.body import Body
from hitogata.errors import HitogataError
from hitogata.export.body_files import body_from_extras, write_body
from hitogata.export.glb_read import read_glb_skin
from hitogata.made_to_measure.solve import (
    MET,
    RESIDUAL_UNIT,
    MadeToMeasure,
    MeasurementWarning,
    allowance,
    body_to_measure,
    judge,
)
from hitogata.measure import measure
from hitogata.body.shape import MODIFIER_NAMES, ShapeParameters

# The example of the issue and the README (cm), with a mass: six measurements.
SIX = {"stature": 1.65, "chest": 0.92, "waist": 0.74, "hip": 1.00, "inside_leg": 0.76, "mass": 60.0}


def within(fit: MadeToMeasure, fraction: float = 1.0) -> dict[str, float]:
    """The residuals (mm; g for the mass) larger than `fraction` of their allowance."""
    return {n: round(r * 1000, 2) for n, r in fit.residuals.items()
            if abs(r) > fraction * allowance(n, fit.requested[n])}


def test_allowances_are_iso_20685() -> None:
    assert allowance("chest_girth") == 0.009
    assert allowance("wrist_girth") == allowance("neck_girth") == allowance("ankle_girth") == 0.004
    assert allowance("inside_leg") == allowance("stature") == allowance("arm_length") == 0.005
    assert allowance("mass", 60.0) == pytest.approx(0.6)


def test_six_measurements_met_within_a_tenth_of_the_allowance() -> None:
    fit = body_to_measure("female", SIX)
    assert within(fit, MET * RESIDUAL_UNIT) == {}
    assert sorted(fit.requested) == ["chest_girth", "hip_girth", "inside_leg", "mass", "stature", "waist_girth"]
    assert fit.body.mass == pytest.approx(60.0, abs=0.06)
    again = measure(fit.body).as_dict()
    assert all(fit.achieved[n] == again[n] for n in fit.requested if n != "mass")
    # The same through the Body constructor, with the short names.
    body = Body.from_measurements(sex="female", **SIX)
    assert body.params == fit.body.params


def test_girths_alone_keep_the_default_stature() -> None:
    fit = body_to_measure("male", {"chest": 1.04, "waist": 0.86})
    assert within(fit, MET * RESIDUAL_UNIT) == {}
    assert fit.body.stature == pytest.approx(1.78, abs=0.005)  # the default man's, not a taller one


def test_stature_or_mass_alone_takes_the_default_build() -> None:
    body = Body.from_measurements("male", stature=1.90)
    assert body.stature == pytest.approx(1.90, abs=1e-4)
    assert body.mass / 1.90**2 == pytest.approx(78.0 / 1.78**2, rel=2e-4)  # the default male's BMI


@pytest.mark.parametrize("asked, message", [
    ({"chest_girht": 0.9}, "measurement 'chest_girht': allowed stature, neck_girth"),
    ({"chest": -0.9}, "chest -0.9 m: allowed a finite positive number"),
    ({"waist": math.nan}, "waist nan m: allowed a finite positive number"),
    ({"stature": 2.5}, "stature 250.0 cm: allowed 140–210 cm"),
    ({"chest": 0.9, "chest_girth": 0.91}, "chest_girth: chest_girth asked twice"),
    ({}, "no measurement asked"),
])
def test_bad_requests_one_line_before_any_work(asked: dict, message: str, monkeypatch) -> None:
    import hitogata.made_to_measure.solve as made

    monkeypatch.setattr(made, "measure", lambda *_: pytest.fail("measured before the mistake was found"))
    with pytest.raises(HitogataError, match="^" + message.replace("(", r"\(").replace(")", r"\)")):
        body_to_measure("female", asked)


def test_judge_warns_near_and_raises_far() -> None:
    body = Body.from_parameters(ShapeParameters())
    asked = {"chest_girth": 0.92, "wrist_girth": 0.15}
    judge(MadeToMeasure(body, asked, {"chest_girth": 0.928, "wrist_girth": 0.153}))  # within: silent
    with pytest.warns(MeasurementWarning, match=r"^met outside the allowance: wrist_girth \+0.6 cm$"):
        judge(MadeToMeasure(body, asked, {"chest_girth": 0.928, "wrist_girth": 0.156}))
    far = MadeToMeasure(body, asked, {"chest_girth": 0.95, "wrist_girth": 0.151})
    with pytest.raises(HitogataError, match=r"^chest_girth 92.0 cm, wrist_girth 15.0 cm: cannot be met together; "
                       r"the nearest body has chest_girth 95.0 cm \(at the limit of weight\)$"):
        judge(far, ["weight"])


@pytest.mark.slow
def test_impossible_request_names_what_cannot_be_met() -> None:
    with pytest.raises(HitogataError) as err:
        body_to_measure("female", {"stature": 1.65, "chest": 0.80, "waist": 1.05, "hip": 0.85})
    message = str(err.value)
    assert "\n" not in message
    assert re.match(r"^stature 165.0 cm, chest_girth 80.0 cm, waist_girth 105.0 cm, hip_girth 85.0 cm: cannot be met "
                    r"together; the nearest body has .*waist_girth \d+.\d cm.* \(at the limit of [^)]+\)$", message), message
    assert "measure-" not in message  # MakeHuman's target names are counted, not listed
    # which other bounds hold the nearest body differs with the platform's solver (measure-waist-circ or not)


# Bodies at the extremes of the supported range, rebuilt from the measurements a size chart gives
# (not the mass: with stature and mass the solve would start at the answer). A woman's heaviest build
# is BMI 33.6 at 150 cm (MakeHuman's max-weight, min-muscle body). The widths between the armpit folds,
# the armscye and the crotch length (and its front and back rise), shoulder and waist-to-hip lengths are left out:
# with them the solve is over-determined on the short heavy woman and the lean men (docs/body.md). The iliac crest's
# waist and height are left out too: no size chart gives them, and their level follows the skeleton's joints (docs/measurements.md).
NOT_ON_A_SIZE_CHART = ("armscye_girth", "across_back_width", "across_front_width", "crotch_length", "front_rise",
                       "back_rise", "shoulder_length", "waist_to_hip_length", "iliac_crest_waist_girth",
                       "iliocristale_height")
EXTREMES = [(sex, stature, bmi) for sex, top in (("female", 33.0), ("male", 35.0))
            for stature in (1.50, 1.95) for bmi in (18.0, top)]


@pytest.mark.slow
@pytest.mark.parametrize("sex, stature, bmi", EXTREMES)
def test_bodies_rebuilt_from_their_measurements(sex: str, stature: float, bmi: float) -> None:
    original = Body.from_measurements(sex, 30.0, stature, bmi * stature**2)
    asked = {n: v for n, v in measure(original).as_dict().items()
             if math.isfinite(v) and n not in NOT_ON_A_SIZE_CHART}
    assert len(asked) == 17
    with warnings.catch_warnings():
        warnings.simplefilter("error", MeasurementWarning)
        fit = body_to_measure(sex, asked)
    assert len(fit.requested) == len(asked)
    assert within(fit) == {}  # girths 9 mm, small girths 4 mm, lengths 5 mm
    assert fit.body.mass == pytest.approx(original.mass, rel=0.02)  # the tape fixes the build well, not wholly


def test_modifiers_checked_sorted_and_blended() -> None:
    params = ShapeParameters(modifiers=(("measure-waist-circ", 0.5), ("measure-bust-circ", -0.25),
                                        ("measure-neck-circ", 0.0)))
    assert params.modifiers == (("measure-bust-circ", -0.25), ("measure-waist-circ", 0.5))
    with pytest.raises(HitogataError, match=r"^modifier measure-waist-circ=1.5: allowed −1..1$"):
        ShapeParameters(modifiers=(("measure-waist-circ", 1.5),))
    with pytest.raises(HitogataError, match=r"^modifier \('measure-belly', 0.5\): allowed \(name, value\)"):
        ShapeParameters(modifiers=(("measure-belly", 0.5),))
    assert len(MODIFIER_NAMES) == 20
    plain = Body.from_parameters(ShapeParameters())
    wider, narrower = (Body.from_parameters(ShapeParameters(modifiers=(("measure-waist-circ", v),))) for v in (1, -0.5))
    # MakeHuman's rule: the incr target at +1, half the decr target at −0.5 (litres, mm).
    assert (wider.volume - plain.volume) * 1000 == pytest.approx(2.575, abs=1e-3)
    assert (narrower.volume - plain.volume) * 1000 == pytest.approx(-1.208, abs=1e-3)
    assert np.abs(wider.vertices - plain.vertices).max() * 1000 == pytest.approx(28.1)
    assert wider.stature == plain.stature


def test_modifiers_kept_in_the_glb(tmp_path: Path) -> None:
    params = ShapeParameters(sex=1.0, modifiers=(("measure-thigh-circ", 0.3), ("measure-neck-height", -0.2)))
    path = write_body(tmp_path / "body.glb", Body.from_parameters(params))
    again = body_from_extras(path, read_glb_skin(path).extras or {})
    assert again.params == params
    np.testing.assert_array_equal(again.vertices, Body.from_parameters(params).vertices)


def run(argv: list[str], capsys) -> tuple[int, str, str]:
    code = cli.main(argv)
    out = capsys.readouterr()
    return code, out.out, out.err


def test_cli_body_from_measurements(tmp_path: Path, capsys) -> None:
    out = tmp_path / "body.glb"
    code, text, err = run(["body", "--sex", "female", "--stature", "165cm", "--chest", "92cm", "--waist-girth",
                           "740mm", "--hip", "1m", "--inside-leg", "76cm", "--out", str(out)], capsys)
    assert code == 0, err
    lines = text.splitlines()
    assert lines[0].startswith(f"{out}: stature 165.0 cm")
    assert sorted(line.split()[0] for line in lines[1:]) == ["chest_girth", "hip_girth", "inside_leg", "stature",
                                                             "waist_girth"]
    body = body_from_extras(out, read_glb_skin(out).extras or {})
    assert abs(measure(body).chest_girth - 0.92) <= MET * RESIDUAL_UNIT * allowance("chest_girth")


def test_cli_size_chart(tmp_path: Path, capsys) -> None:
    chart = tmp_path / "chart.csv"
    chart.write_text("size,stature_cm,chest_girth_cm,waist_cm,hip_girth_cm,mass_kg\n"
                     "S,160,84,66,90,\nM,165,90,,96,58\n")
    out = tmp_path / "sizes"
    code, text, err = run(["body", "--sex", "female", "--size-chart", str(chart), "--out", str(out)], capsys)
    assert code == 0, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["chart.csv", "sizes"]  # no staging folder left
    assert sorted(p.name for p in out.iterdir()) == ["M.glb", "S.glb", "sizes.csv"]
    rows = (out / "sizes.csv").read_text().splitlines()
    assert rows[0] == "size,measurement,asked,made,difference,unit"
    assert sorted(",".join(r.split(",")[:3]) for r in rows[1:]) == [
        "M,chest_girth,90.00", "M,hip_girth,96.00", "M,mass,58.00", "M,stature,165.00",
        "S,chest_girth,84.00", "S,hip_girth,90.00", "S,stature,160.00", "S,waist_girth,66.00"]
    assert all(abs(float(r.split(",")[4])) <= 0.1 for r in rows[1:])
    assert text.splitlines()[-1] == f"2 sizes; wrote S.glb, M.glb and sizes.csv in {out}/"


@pytest.mark.parametrize("content, message", [
    ("", "chart.csv: empty; allowed a header"),
    ("name,stature_cm\nS,160\n", "chart.csv: first column 'name'; allowed 'size'"),
    ("size,stature_in\nS,60\n", "chart.csv: column 'stature_in': allowed <measurement>_<unit>"),
    ("size,mass_cm\nS,60\n", "chart.csv: column 'mass_cm': allowed <measurement>_<unit>"),
    ("size,chest_cm,chest_girth_mm\nS,90,900\n", "chart.csv: chest_girth is in two columns; allowed once"),
    ("size,stature_cm\n", "chart.csv: no sizes; allowed one row per size under the header"),
    ("size,stature_cm,chest_cm\nS,160,84\nM,165\n", "chart.csv: row 3: 2 cells; allowed 3"),
    ("size,stature_cm,chest_cm\nS,160,84\nM,165,9O\n", "chart.csv: row 3, column chest_cm: '9O'; allowed a number"),
    ("size,stature_cm\nS,-160\n", "chart.csv: row 2, column stature_cm: '-160'; allowed a positive number"),
    ("size,stature_cm\nS,160\nS,165\n", "chart.csv: row 3, column size: 'S' is named twice; allowed once"),
    ("size,stature_cm\n../x,160\n", "chart.csv: row 2, column size: '../x'; allowed letters, digits"),
    ("size,stature_cm\nS,\n", "chart.csv: row 2: size 'S' has no measurement; allowed at least one"),
    ("size,stature_cm,chest_cm\nS,160,84\nXL,250,120\n", "chart.csv: size XL: stature 250.0 cm: allowed 140–210"),
])
def test_size_chart_mistakes_one_line_nothing_written(tmp_path: Path, capsys, monkeypatch, content: str,
                                                      message: str) -> None:
    import hitogata.made_to_measure.solve as made

    monkeypatch.setattr(made, "measure", lambda *_: pytest.fail("measured before the mistake was found"))
    monkeypatch.chdir(tmp_path)
    Path("chart.csv").write_text(content)
    code, _, err = run(["body", "--size-chart", "chart.csv", "--out", "sizes"], capsys)
    assert code == 2
    assert err.count("\n") == 1 and err.startswith(f"hitogata: error: {message}"), err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["chart.csv"]


@pytest.mark.parametrize("args, message", [
    (["--chest", "92"], "--chest '92': write a number with a unit"),
    (["--hip", "-1m"], "--hip -1m: allowed a positive length, e.g. 80cm"),
    (["--size-chart", "chart.csv", "--waist", "70cm"], "--waist: does not apply with --size-chart"),
    (["--size-chart", "chart.csv", "--stature", "170cm"], "--stature: does not apply with --size-chart"),
])
def test_measurement_option_mistakes(tmp_path: Path, capsys, monkeypatch, args: list[str], message: str) -> None:
    monkeypatch.chdir(tmp_path)
    Path("chart.csv").write_text("size,stature_cm\nS,160\n")
    out = "sizes" if "--size-chart" in args else "body.glb"
    code, _, err = run(["body", *args, "--out", out], capsys)
    assert code == 2
    assert err.count("\n") == 1 and err.startswith(f"hitogata: error: {message}"), err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["chart.csv"]


@pytest.mark.slow
def test_jacobian_from_the_tapes_agrees_with_whole_body_differences() -> None:
    """The steering rows (skin motion along the tapes and paths) against measuring one body per
    unknown, at a point away from every kink of the blend."""
    from hitogata.made_to_measure.solve import _Problem, checked_request

    problem = _Problem(ShapeParameters(sex=0.0), checked_request({"chest": 0.92, "arm_length": 0.52}), 1000.0,
                       None, None)
    x = np.r_[np.full(len(problem.macros), 0.57), np.random.default_rng(1).uniform(-0.3, 0.3, len(MODIFIER_NAMES))]
    rows = problem.jacobian(x)[:2] * problem.scale[:2, None]  # (the third: the soft stature)
    agree = {}
    for row, name in zip(rows, problem.names):
        whole = problem.differenced_row(x, name)
        agree[name] = (round(float(row @ whole / np.linalg.norm(row) / np.linalg.norm(whole)), 3),
                       round(float(np.linalg.norm(row) / np.linalg.norm(whole)), 3))
    # (cosine, length ratio). The bust tape's plane goes through the bust points wherever the cup
    # takes them, while the tape's points here ride the skin: the cup's column is 0.23 against 0.15.
    assert agree == {"chest_girth": (0.989, 1.031), "arm_length": (1.0, 1.008)}
