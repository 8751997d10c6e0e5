"""Children in study and scenario files: sampled from the growth references, run on Dask as adults
are, and the same one-line errors as the CLI for an age, stature or mass the references refuse."""

from pathlib import Path

import numpy as np
import pytest

from hitogata.body import growth
from hitogata.body import mass_range
from hitogata.cli import main
from hitogata.motion.scenario import load_scenario
from hitogata.errors import HitogataError
from hitogata.study.child_sampling import sample_children
from hitogata.study.results import read_failures, read_rows
from hitogata.study.runner import run_on_client
from hitogata.study.spec import load_study

STUDIES = Path(__file__).parents[2] / "src" / "hitogata" / "data" / "studies"


def test_bmi_for_age_gives_whos_figures_and_a_toddlers_bmi_is_on_length():
    # WHO 2007 BMI-for-age, boys 72 months: M 15.3062, +2 SD 18.5 (the z-score table, to 0.1)
    assert growth.median("bmi", 1.0, 6.0) == pytest.approx(15.3062, abs=1e-4)
    assert growth.at_percentile("bmi", 1.0, 6.0, 100 * 0.977250) == pytest.approx(18.5, abs=0.05)
    # WHO 2006 BMI-for-age, girls 24 months (the 2–5 years table, on height): M 15.6881
    assert growth.median("bmi", 0.0, 2.0) == pytest.approx(15.6881, abs=1e-4)
    # below 24 months WHO's BMI is on recumbent length: the standing stature plus 0.7 cm
    assert growth.mass_of_bmi(np.array(16.0), np.array(0.75), 1.0) == pytest.approx(16.0 * 0.757**2)
    assert growth.mass_of_bmi(np.array(16.0), np.array(0.90), 2.0) == pytest.approx(16.0 * 0.90**2)


@pytest.mark.parametrize("sex", ["female", "male"])
def test_sampled_six_year_olds_follow_the_references_percentiles(sex):
    """Stature's 5th/50th/95th percentiles are the height-for-age's (the truncation to 0.1–99.9 and
    to the shape's reach moves them by well under 1 cm: 0.3 cm at most here), BMI is drawn apart
    from stature (|r| within 4 standard errors of 0), and the masses so made have weight-for-age's
    median within 0.5 kg and its 5th and 95th percentiles within 6 % (WHO 2007 at 6 years; drawn
    apart, stature and BMI give a mass a little narrower than weight-for-age's: its 95th
    percentile 2.5–4 % under WHO's at this age)."""
    drawn = sample_children(sex, 6.0, 3000, 2007)
    stature, mass = drawn.values.T
    male = float(sex == "male")
    for p in (5, 50, 95):
        assert abs(np.percentile(stature, p) - growth.at_percentile("stature", male, 6.0, p)) < 0.006
    assert abs(np.percentile(mass, 50) - growth.at_percentile("mass", male, 6.0, 50)) < 0.5
    for p in (5, 95):
        assert abs(np.percentile(mass, p) / growth.at_percentile("mass", male, 6.0, p) - 1.0) < 0.06
    assert abs(np.corrcoef(stature, mass / stature**2)[0, 1]) < 4 / np.sqrt(len(stature))
    assert drawn.kept_share > 0.95


def test_the_shipped_childrens_study_refuses_none_of_its_bodies():
    """Every sampled child lies within the references' 0.1–99.9 percentiles and within the mass the
    shape builds at its stature (checked at the lightest and heaviest for stature of each sex)."""
    spec = load_study(STUDIES / "children.toml")
    assert len(spec.bodies) == 100 and {b.age for b in spec.bodies} == {6.0}
    assert "WHO BMI-for-age" in spec.population
    for sex in ("female", "male"):
        bodies = [b for b in spec.bodies if b.sex == sex]
        assert len(bodies) == 50
        for b in bodies:
            growth.check_child(float(sex == "male"), b.age, b.stature, b.mass)
        bmi = [b.mass / b.stature**2 for b in bodies]
        for b in (bodies[int(np.argmin(bmi))], bodies[int(np.argmax(bmi))]):
            low, high = mass_range(sex, b.age, b.stature)
            assert low < b.mass < high


@pytest.mark.slow
def test_a_childrens_study_runs_on_the_local_cluster(client, tmp_path):
    """Four sampled six-year-olds through raising the arms, by skinning at 2 frames: every task done,
    none refused, and the shoulders stretch as the adults' do."""
    path = tmp_path / "children.toml"
    path.write_text(f'motions = ["{STUDIES / "arms_raised.toml"}"]\nseed = 6\n'
                    '[bodies]\nsampled = 4\nage = 6\nclusters = 2\n[model]\nframes = 2\n', encoding="utf-8")
    spec = load_study(path)
    summary = run_on_client(spec, tmp_path / "out", client)
    assert (summary.done, summary.failed) == (4, 0)
    assert read_failures(tmp_path / "out") == []
    rows = read_rows(tmp_path / "out")
    assert set(rows["age"].tolist()) == {6.0}
    statures = sorted(set(np.round(rows["stature_m"], 4).tolist()))
    assert statures == sorted(round(b.stature, 4) for b in spec.bodies)
    zone = (rows["kind"] == "zone") & (rows["name"] == "shoulder_right")
    assert zone.sum() == 4 and np.all(rows["stretch_p95_pct"][zone] > 30.0)


def _study(tmp_path: Path, bodies: str) -> Path:
    path = tmp_path / "s.toml"
    path.write_text(f'motions = ["rectus_stretch"]\n[bodies]\n{bodies}\n', encoding="utf-8")
    return path


@pytest.mark.parametrize("bodies, message", [
    ("sampled = 4\nage = 0.5", "s.toml: [bodies].age: 0.5 is out of range; allowed years, 1..90"),
    ("sampled = 4\nage = 6\n[bodies.women]\nstature_mean = \"115cm\"",
     "s.toml: [bodies].women: age 6 with women statistics; allowed for adults (18..90): children are drawn"),
])
def test_bad_childrens_study_is_one_line(tmp_path, bodies, message):
    with pytest.raises(HitogataError) as err:
        load_study(_study(tmp_path, bodies))
    assert str(err.value).startswith(str(tmp_path / message))
    assert "\n" not in str(err.value)


@pytest.mark.parametrize("row, message", [
    ("S,female,150,20,6", "row 2 (size 'S'): stature 150.0 cm at age 6: allowed 99.3–130.9 cm for this sex and age, "
                          "the growth references' percentiles 0.1–99.9"),
    ("S,male,116,45,6", "row 2 (size 'S'): mass 45.0 kg at age 6: allowed"),
    ("S,male,116,20,0.5", "row 2 (size 'S'): age_years '0.5'; allowed a number 1..90 years"),
])
def test_bad_childrens_chart_row_is_the_clis_line_with_the_row(tmp_path, row, message):
    (tmp_path / "x.csv").write_text(f"size,sex,stature_cm,mass_kg,age_years\n{row}\n", encoding="utf-8")
    with pytest.raises(HitogataError) as err:
        load_study(_study(tmp_path, 'chart = "x.csv"'))
    assert str(err.value).startswith(f"{tmp_path / 'x.csv'}: {message}")


def test_a_childrens_chart_gives_its_rows(tmp_path):
    (tmp_path / "x.csv").write_text("size,sex,stature_cm,mass_kg,age_years\n116,female,116,21,6\n", encoding="utf-8")
    (body,) = load_study(_study(tmp_path, 'chart = "x.csv"')).bodies
    assert (body.group, body.age, body.stature, body.mass) == ("116", 6.0, 1.16, 21.0)


SCENARIO = '[time]\nduration = "1s"\n[[keyframe]]\ntime = "0s"\n[body]\nsex = "female"\n'


@pytest.mark.parametrize("body, message", [
    ("age = 0.5", "[body].age: 0.5 is out of range; allowed years, 1..90"),
    ('age = 6\nstature = "150cm"\nmass = "20kg"',
     "[body]: stature 150.0 cm at age 6: allowed 99.3–130.9 cm for this sex and age, the growth references' "
     "percentiles 0.1–99.9"),
    ('age = 30\nstature = "160cm"\nmass = "140kg"', "[body]: mass 140.0 kg at stature 160.0 cm: BMI 54.7, allowed up "
     "to 50 (128.0 kg) for adults"),
])
def test_scenario_body_takes_ages_1_to_90_with_the_clis_errors(tmp_path, capsys, body, message):
    path = tmp_path / "sc.toml"
    path.write_text(SCENARIO + body + "\n", encoding="utf-8")
    with pytest.raises(HitogataError) as err:
        load_scenario(path)
    assert str(err.value).startswith(f"{path}: {message}")
    assert main(["simulate", str(path), "--out", str(tmp_path / "out")]) == 2
    assert capsys.readouterr().err.strip().startswith(f"hitogata: error: {path}: {message}")
    assert not (tmp_path / "out").exists()


def test_scenario_takes_a_child(tmp_path):
    path = tmp_path / "sc.toml"
    path.write_text(SCENARIO + 'age = 6\nstature = "116cm"\nmass = "21kg"\n', encoding="utf-8")
    body = load_scenario(path).body
    assert (body.age, body.stature, body.mass) == (6.0, 1.16, 21.0)
