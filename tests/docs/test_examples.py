"""The examples gallery runs: each script in examples/ as a user runs it, into a temporary folder,
printing its figures and writing its files (`python examples/NN_name.py OUT`).

The figures checked are the method's, with its tolerances: a body has the stature and mass asked
for, made to measure meets the tape within ISO 20685-1's allowances, a scan fit comes within 2 mm,
the resolved contact leaves no skin inside another part. Each example keeps its model coarse so the
gallery stays a couple of minutes of CPU in all.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = REPO / "examples"


def run_example(name: str, out: Path) -> str:
    """Run examples/`name` with `out` as its folder; its standard output (fails with its stderr)."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(REPO / "src"), os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run([sys.executable, str(EXAMPLES / name), str(out)], capture_output=True, text=True,
                          env=env, cwd=out)
    assert done.returncode == 0, f"{name} failed:\n{done.stdout}\n{done.stderr}"
    return done.stdout


def number(pattern: str, text: str) -> float:
    found = re.search(pattern, text)
    assert found, f"{pattern!r} not in:\n{text}"
    return float(found.group(1))


def test_the_gallery_is_numbered_and_covers_the_library():
    names = sorted(p.name for p in EXAMPLES.glob("[0-9][0-9]_*.py"))
    assert [n[:2] for n in names] == [f"{i:02d}" for i in range(1, len(names) + 1)]
    for topic in ("body", "made_to_measure", "scan_fit", "pose", "elastic_pose_contact", "simulate",
                  "dynamic_ease", "fit_report", "study", "garment_pressure", "motion_capture"):
        assert any(topic in n for n in names), topic
    tutorial = (REPO / "docs" / "tutorial.md").read_text(encoding="utf-8")
    for n in names:
        assert f"examples/{n}" in tutorial, f"docs/tutorial.md does not link examples/{n}"


def test_01_body(tmp_path):
    out = run_example("01_body.py", tmp_path)
    assert number(r"stature ([\d.]+) cm", out) == pytest.approx(165.0, abs=0.05)
    assert number(r"mass ([\d.]+) kg", out) == pytest.approx(58.0, abs=0.05)
    assert 60 < number(r"waist_girth\s+([\d.]+) cm", out) < 80
    assert (tmp_path / "body.glb").stat().st_size > 100_000


def test_02_made_to_measure(tmp_path):
    out = run_example("02_made_to_measure.py", tmp_path)
    assert "outside the allowance" not in out
    assert number(r"largest difference ([\d.]+) mm", out) <= 5.0  # ISO 20685-1: 5 mm lengths, 9 mm large girths
    assert (tmp_path / "made.glb").is_file()


@pytest.mark.slow
def test_03_scan_fit(tmp_path):
    out = run_example("03_scan_fit.py", tmp_path)
    assert number(r"median ([\d.]+) mm", out) <= 2.0
    for girth in ("chest", "waist", "hip"):
        assert abs(number(rf"{girth}_girth .* ([+-][\d.]+) mm", out)) <= 9.0  # a large girth's allowance
    assert (tmp_path / "fitted.glb").is_file()


def test_04_pose(tmp_path):
    out = run_example("04_pose.py", tmp_path)
    assert number(r"shank_r.flexion .*-> +([\d.]+)°", out) == pytest.approx(60.0, abs=0.05)
    assert number(r"forearm_l.flexion .*-> +([\d.]+)°", out) > number(r"forearm_l.flexion +([\d.]+)°", out) + 20
    rest, posed = number(r"waist ([\d.]+) cm at rest", out), number(r"([\d.]+) cm posed", out)
    assert posed == pytest.approx(rest, abs=0.2)  # an elbow and a knee do not move the waist
    assert (tmp_path / "posed.glb").is_file()


@pytest.mark.slow
def test_05_elastic_pose_contact(tmp_path):
    out = run_example("05_elastic_pose_contact.py", tmp_path)
    assert number(r"without contact: +(\d+) skin vertices inside", out) > 10  # skinning's overlap at 150°
    assert number(r"with contact +: +(\d+) skin vertices inside", out) == 0
    assert number(r"smallest gap ([\d.]+) mm", out) > 0
    assert (tmp_path / "elbow_elastic.ply").is_file()


@pytest.mark.slow
def test_06_simulate(tmp_path):
    out = run_example("06_simulate.py", tmp_path)
    assert "largest skin displacement by the elastic body" in out
    assert 0 < number(r"lowest frequencies: ([\d.]+)", out) < 10  # Hz: soft tissue on a held skeleton
    assert (tmp_path / "results" / "motion.glb").is_file()


def test_07_dynamic_ease(tmp_path):
    out = run_example("07_dynamic_ease.py", tmp_path)
    assert number(r"knee_girth .* \+ *([\d.]+) cm \(deep_squat", out) > 5  # a deep squat opens the knee
    assert (tmp_path / "ease.csv").read_text().count("\n") > 10


@pytest.mark.slow
def test_08_fit_report(tmp_path):
    out = run_example("08_fit_report.py", tmp_path)
    assert "ease.json: 2 motions" in out
    page = (tmp_path / "fit_report" / "fit_report.html").read_text(encoding="utf-8")
    assert "<html" in page.lower() and "knee" in page


@pytest.mark.slow
def test_09_study(tmp_path):
    out = run_example("09_study.py", tmp_path)
    bodies = number(r"dynamic ease of across_back_width +over (\d+) bodies", out)
    failed = number(r"(\d+) failed task", out)
    assert bodies + failed == 6
    assert number(r"across_back_width .* P50 ([\d.]+)", out) > 0  # reaching forward widens the back
    assert (tmp_path / "results" / "percentiles.csv").is_file()


def test_10_garment_pressure(tmp_path):
    out = run_example("10_garment_pressure.py", tmp_path)
    ankle, calf = (number(rf"{level} +[\d.]+ +([\d.]+) /", out) for level in ("ankle", "calf"))
    assert ankle > calf  # the same strain on a smaller radius: graduated compression comes free
    knee_standing, knee_seated = number(r"knee +[\d.]+ +([\d.]+) /", out), number(r"knee .* ([\d.]+) / +[\d.]+\n", out)
    assert knee_seated > knee_standing  # sitting stretches the garment over the knee
    assert (tmp_path / "pressure.csv").read_text().count("\n") == 13  # header + 6 levels × 2 postures


def test_11_motion_capture(tmp_path):
    out = run_example("11_motion_capture.py", tmp_path)
    assert number(r"largest joint-angle difference ([\d.e+-]+)°", out) < 0.01  # the 6-decimal file's round-off
    assert number(r"read back: (\d+) frames", out) == number(r"reach.bvh: (\d+) frames", out)

