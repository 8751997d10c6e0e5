"""Study files: sampling reproduces the requested statistics; bad input is one line naming file, entry, value."""

from pathlib import Path

import numpy as np
import pytest

from hitogata.cli import main
from hitogata.errors import HitogataError
from hitogata.study.sampling import Joint, clusters, sample_stature_mass, sex_counts
from hitogata.study.spec import load_study
from hitogata.study.tasks import Task

EXAMPLE = Path(__file__).parents[2] / "src" / "hitogata" / "data" / "studies" / "example.toml"
WOMEN = Joint(1.629, 0.064, 67.8, 11.1, 0.53, "test")
MEN = Joint(1.756, 0.069, 85.5, 14.2, 0.53, "test")


@pytest.mark.parametrize("joint, sex", [(WOMEN, "female"), (MEN, "male")])
def test_sampled_stature_and_mass_reproduce_means_sds_and_correlation(joint, sex):
    n = 40_000
    x = sample_stature_mass(joint, n, seed=7, sex=sex)
    mean, sd = x.mean(axis=0), x.std(axis=0, ddof=1)
    r = np.corrcoef(x.T)[0, 1]
    # Standard errors of a normal sample: mean σ/√n, SD σ/√(2n), correlation (1 − ρ²)/√n; allow 4 of them.
    sigma = np.array([joint.stature_sd, joint.mass_sd])
    assert np.all(np.abs(mean - joint.mean) < 4 * sigma / np.sqrt(n))
    assert np.all(np.abs(sd - sigma) < 4 * sigma / np.sqrt(2 * n))
    assert abs(r - joint.correlation) < 4 * (1 - joint.correlation**2) / np.sqrt(n)
    # Reproducible from the seed; another seed, other bodies.
    assert np.array_equal(x, sample_stature_mass(joint, n, seed=7, sex=sex))
    assert not np.array_equal(x[:10], sample_stature_mass(joint, 10, seed=8, sex=sex))


def test_each_sex_draws_from_its_own_stream():
    assert np.array_equal(sample_stature_mass(WOMEN, 5, 3, "female"), sample_stature_mass(WOMEN, 50, 3, "female")[:5])
    assert not np.array_equal(sample_stature_mass(WOMEN, 5, 3, "female"), sample_stature_mass(WOMEN, 5, 3, "male"))
    assert sex_counts(7, 0.5) == {"female": 4, "male": 3}


def test_clusters_are_ordered_by_mass():
    x = sample_stature_mass(WOMEN, 300, 1, "female")
    labels = clusters(x, 3, 1)
    means = [x[labels == c, 1].mean() for c in range(3)]
    assert sorted(set(labels.tolist())) == [0, 1, 2] and means == sorted(means)


def test_example_study_loads():
    spec = load_study(EXAMPLE)
    assert len(spec.bodies) == 200 and [m.name for m in spec.motions] == ["arms_raised", "sit"]
    assert sum(b.sex == "female" for b in spec.bodies) == 100
    assert spec.model.posing == "skinning" and spec.model.frames == 9
    assert "ANSUR II" in spec.population
    assert len({b.group for b in spec.bodies}) == 6  # three clusters per sex
    # A task's name is a hash of its definition: the same study gives the same names.
    assert Task(spec.bodies[0], spec.motions[0], spec.model, spec.outputs).key == \
        Task(load_study(EXAMPLE).bodies[0], spec.motions[0], spec.model, spec.outputs).key


def _study(tmp_path: Path, bodies: str, extra: str = "") -> Path:
    path = tmp_path / "s.toml"
    path.write_text(f'motions = ["rectus_stretch"]\n{extra}\n[bodies]\n{bodies}\n', encoding="utf-8")
    return path


SAMPLED = """sampled = 10
female = 1.0
[bodies.women]
stature_mean = "163cm"
stature_sd = "6cm"
mass_mean = "68kg"
mass_sd = "11kg"
correlation = {r}
source = {source}
"""


@pytest.mark.parametrize("bodies, extra, message", [
    (SAMPLED.format(r=1.5, source='"x"'), "", "s.toml: [bodies.women].correlation: 1.5 is out of range; allowed a number -0.99..0.99"),
    (SAMPLED.format(r=0.5, source='""'), "", "s.toml: [bodies.women].source: ''; allowed the published survey"),
    (SAMPLED.format(r=0.5, source='"x"').replace('"6cm"', '"6kg"'), "",
     "s.toml: [bodies.women].stature_sd: '6kg' is not a length like 163cm"),
    ("sampled = 10\nfemale = 0.0", "", "s.toml: [bodies].men: missing; allowed a table of correlation, mass_mean"),
    (SAMPLED.format(r=0.5, source='"x"').replace('mass_sd = "11kg"', ""), "",
     "s.toml: [bodies.women]: missing key 'mass_sd'; it has no default"),
    ('sampled = 3\nchart = "x.csv"', "", "s.toml: [bodies]: sampled and chart given; allowed exactly one"),
    ("", "", "s.toml: [bodies]: none given; allowed exactly one"),
    ("sampled = 0", "", "s.toml: [bodies].sampled: 0; allowed a whole number 1..1000000"),
    ('chart = "x.csv"', 'outputs = ["ease"]', "s.toml: file.outputs: ['ease']; allowed a list of measurements"),
    ('chart = "x.csv"', '[model]\nposing = "rigid"', "s.toml: [model].posing: 'rigid'; allowed skinning, elastic"),
    ('chart = "x.csv"', "[model]\nframes = 1", "s.toml: [model].frames: 1; allowed a whole number 2..200"),
])
def test_bad_study_is_one_line_naming_file_entry_value(tmp_path, bodies, extra, message):
    with pytest.raises(HitogataError) as err:
        load_study(_study(tmp_path, bodies, extra))
    assert str(err.value).startswith(str(tmp_path / message.split(":")[0]) + ":" + message.split(":", 1)[1])
    assert "\n" not in str(err.value)


def test_unknown_motion_names_the_shipped_ones(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text('motions = ["moonwalk"]\n[bodies]\nchart = "x.csv"\n', encoding="utf-8")
    with pytest.raises(HitogataError, match=r"s.toml: file.motions: 'moonwalk'; allowed a scenario file or a "
                                            r"shipped scenario: .*rectus_stretch"):
        load_study(path)


@pytest.mark.parametrize("csv, message", [
    ("size,sex,stature_cm,mass_kg\nM,female,165,abc\n", "x.csv: row 2 (size 'M'): mass_kg 'abc'; allowed a number 30..200 kg"),
    ("size,sex,stature_cm,mass_kg\nM,woman,165,60\n", "x.csv: row 2 (size 'M'): sex 'woman'; allowed female, male"),
    ("size,sex,stature_in,mass_kg\nM,female,65,60\n", "x.csv: header size,sex,stature_in,mass_kg: no 'stature' column"),
    ("size,sex,stature_m,mass_kg\nS,male,1.2,60\n", "x.csv: row 2 (size 'S'): stature_m '1.2'; allowed a number 140..210 cm"),
])
def test_bad_size_chart_is_one_line_naming_row_and_value(tmp_path, csv, message):
    (tmp_path / "x.csv").write_text(csv, encoding="utf-8")
    with pytest.raises(HitogataError) as err:
        load_study(_study(tmp_path, 'chart = "x.csv"'))
    assert str(err.value).startswith(str(tmp_path / message))


def test_size_chart_units_in_the_header(tmp_path):
    (tmp_path / "x.csv").write_text("size,sex,stature_m,mass_g,age_years\nS,female,1.55,52000,40\n", encoding="utf-8")
    (body,) = load_study(_study(tmp_path, 'chart = "x.csv"')).bodies
    assert (body.group, body.sex, body.stature, body.mass, body.age) == ("S", "female", 1.55, 52.0, 40.0)


def test_cli_bad_study_exits_2_with_one_line(tmp_path, capsys):
    path = _study(tmp_path, SAMPLED.format(r=2, source='"x"'))
    assert main(["study", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert err == f"hitogata: error: {path}: [bodies.women].correlation: 2 is out of range; allowed a number -0.99..0.99"
    assert not (tmp_path / "out").exists()


def test_cli_bad_scheduler_address_exits_2(tmp_path, capsys):
    (tmp_path / "x.csv").write_text("size,sex,stature_cm,mass_kg\nM,female,165,62\n", encoding="utf-8")
    path = _study(tmp_path, 'chart = "x.csv"')
    assert main(["study", str(path), "--out", str(tmp_path / "out"), "--scheduler", "http://x:1"]) == 2
    assert capsys.readouterr().err.strip() == (
        "hitogata: error: --scheduler 'http://x:1': allowed an address like tcp://host:8786")
    assert not (tmp_path / "out").exists()


def test_a_folder_of_body_files_gives_their_shapes(tmp_path):
    from hitogata.body import Body
    from hitogata.export.body_files import write_body
    from hitogata.study.tasks import prepared

    (tmp_path / "bodies").mkdir()
    body = Body.from_measurements("male", 40, 1.85, 95.0)
    write_body(tmp_path / "bodies" / "tall.glb", body)
    (definition,) = load_study(_study(tmp_path, 'folder = "bodies"')).bodies
    assert (definition.id, definition.group, definition.sex, definition.age) == ("tall", "male", "male", 40.0)
    rebuilt = prepared(definition).body
    assert rebuilt.params == body.params and np.array_equal(rebuilt.vertices, body.vertices)


def test_an_empty_body_folder_is_one_line(tmp_path):
    (tmp_path / "bodies").mkdir()
    with pytest.raises(HitogataError, match=r"s.toml: \[bodies\].folder: '.*bodies'; allowed a folder holding "
                                            r"\.glb files written by `hitogata body`$"):
        load_study(_study(tmp_path, 'folder = "bodies"'))


class _Stream:
    def __init__(self, tty: bool) -> None:
        self.tty, self.text = tty, ""

    def isatty(self) -> bool:
        return self.tty

    def write(self, text: str) -> None:
        self.text += text

    def flush(self) -> None:
        pass


def test_progress_line_rewrites_a_terminal_and_does_not_flood_a_log():
    from hitogata.study.progress import ProgressLine
    from hitogata.study.runner import RunSummary

    def run(stream, interval):
        progress = ProgressLine(stream, interval)
        for k in range(1, 101):
            progress(RunSummary(total=110, skipped=10, done=k - (k > 50), failed=int(k > 50), wall_seconds=k * 0.6))
        return stream.text

    log = run(_Stream(False), 1e9).splitlines()  # a log: the first line, one per tenth of the study, the last
    assert len(log) == 11 and "\r" not in "".join(log)
    assert log[:2] == ["11/110 tasks (10 done before), 0 failed, 100.0 tasks/min, 0 min 59 s left",
                       "20/110 tasks (10 done before), 0 failed, 100.0 tasks/min, 0 min 54 s left"]
    assert log[-1] == "110/110 tasks (10 done before), 1 failed, 100.0 tasks/min"
    terminal = run(_Stream(True), 0.0)  # a terminal: rewritten in place, a newline at the end only
    assert terminal.count("\r") == 100 and terminal.count("\n") == 1 and terminal.endswith("1 failed, 100.0 tasks/min\n")


def test_dynamic_ease_is_the_largest_increase_and_decrease_over_standing():
    from hitogata.study.tasks import dynamic_ease

    assert dynamic_ease(1.0, np.array([1.0, 1.02, np.nan, 0.99])) == pytest.approx((0.02, -0.01))
    assert dynamic_ease(1.0, np.array([1.01, 1.03])) == pytest.approx((0.03, 0.0))  # never below standing
    assert all(np.isnan(dynamic_ease(1.0, np.array([np.nan, np.nan]))))
