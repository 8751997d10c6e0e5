"""The README's command-line examples run in the order written (tools/readme_examples.py).

Always: the order is checked (every file an example reads was made by an
earlier one, each `measure` writes its own folder), and the quick examples
run for real in a temporary folder. The long ones (`modes`, `simulate`, `demo`, `study`, `ease`,
`validate`, `identify`: minutes each; `dress`, `fit`: some seconds to a minute) run with them when
HITOGATA_README_ALL=1; `view` is a server and never runs here.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "tools"))
from readme_examples import SERVERS, examples, run  # noqa: E402

LONG = ("modes", "simulate", "demo", "study", "ease", "fit-report", "fit", "dress", "validate", "identify")


def outputs(argv: list[str]) -> str | None:
    return argv[argv.index("--out") + 1].rstrip("/") if "--out" in argv else None


def test_every_example_reads_only_files_made_before_it():
    made: set[str] = set()
    measured: list[str] = []
    for argv in examples():
        if argv[1] == "measure" and len(argv) > 2 and not argv[2].startswith("-"):
            assert argv[2].rstrip("/") in made, f"{' '.join(argv)}: {argv[2]} is made later (or never)"
        if argv[1] == "measure":
            measured.append(outputs(argv))
        if outputs(argv):
            made.add(outputs(argv))
    assert len(measured) == len(set(measured)) == 3, "each measure example writes its own folder"


@pytest.fixture
def worktree_python_path(monkeypatch):
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(REPO / "src"), os.environ.get("PYTHONPATH", "")]))


def test_the_quick_examples_run_in_order(tmp_path, worktree_python_path):
    pytest.importorskip("pyvista", reason="the skeleton example draws offscreen")
    skipped = (*SERVERS, *LONG)
    done = run(tmp_path, skip=skipped)  # and `measure results/`, which reads simulate's folder
    assert [a[1] for a in done][:10] == ["body"] * 6 + ["measure", "pose", "measure", "skeleton"]
    for name in ("body.glb", "body.obj", "measured.glb", "made.glb", "sizes/sizes.csv", "posed.glb", "skeleton.png",
                 "report_body/measurements.json", "report_posed/measurements.json"):
        assert (tmp_path / name).is_file(), name


@pytest.mark.skipif(os.environ.get("HITOGATA_README_ALL") != "1",
                    reason="the long examples (modes, simulate, demo, study, ease, fit-report, fit, dress, validate, "
                           "identify) take minutes: "
                           "HITOGATA_README_ALL=1")
def test_all_examples_run_in_order(tmp_path, worktree_python_path):
    done = run(tmp_path)
    assert len(done) == len(examples()) - len(SERVERS)
    assert (tmp_path / "report_motion" / "measurements_over_time.csv").is_file()
