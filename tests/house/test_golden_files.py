"""The golden files (`tests/golden.py`): a figure within its tolerance passes, one beyond it fails naming the
key, `--repin` writes what the tests compute and lists what moved."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from golden import FOLDER, GoldenFile, golden_path, plain


def test_a_figure_within_its_tolerance_passes_and_one_beyond_fails(tmp_path):
    path = tmp_path / "module.json"
    path.write_text(json.dumps({"female.hip_girth": 1.01733, "female.frequencies": [2.1369, 2.2729]}))
    figures = GoldenFile(path, repin=False)
    figures.check("female.hip_girth", np.float64(1.01736), abs=5e-5)
    figures.check("female.frequencies", np.array([2.1370, 2.2731]), rel=1e-3)
    with pytest.raises(AssertionError, match="female.hip_girth moved"):
        figures.check("female.hip_girth", 1.0180, abs=5e-5)
    with pytest.raises(pytest.fail.Exception, match="no figure 'male.hip_girth'"):
        figures.check("male.hip_girth", 1.0)


def test_repinning_keeps_the_new_figures_and_what_moved(tmp_path):
    path = tmp_path / "sub" / "module.json"
    figures = GoldenFile(path, repin=True)
    figures.check("a", np.array([1.234567891, 2.0]))
    figures.check("b", {"x": np.int64(3)})
    figures.write()
    again = GoldenFile(path, repin=True)
    assert again.figures == {"a": [1.234568, 2.0], "b": {"x": 3}}
    again.check("a", [1.234568, 2.0])
    again.check("b", {"x": 4})
    assert again.moved == {"b": ({"x": 3}, {"x": 4})}
    assert plain(float("nan")) != plain(float("nan")) and plain(np.float32(0.1)) == 0.1


def test_every_golden_file_belongs_to_a_test_module():
    for path in FOLDER.rglob("*.json"):
        module = Path(__file__).parents[1] / path.relative_to(FOLDER).with_suffix(".py")
        assert module.is_file(), f"{path} has no test module"
        assert golden_path(module) == path
        json.loads(path.read_text())


def test_repin_runs_the_tests_and_prints_what_moved(tmp_path):
    """`pytest --repin` on a test module of its own: the golden file written, the moved figure listed."""
    tests = Path(__file__).parents[1]
    module = tests / "house" / f"test_golden_probe_{os.getpid()}.py"
    module.write_text("def test_probe(golden):\n    golden.check('probe.value', 2.5, abs=1e-9)\n")
    written = golden_path(module)
    try:
        run = subprocess.run([sys.executable, "-m", "pytest", "-q", "-n0", "-p", "no:cacheprovider", "--repin",
                              str(module)], capture_output=True, text=True, cwd=tests.parent)
        assert run.returncode == 0, run.stdout + run.stderr
        assert "probe.value: None -> 2.5" in run.stdout
        assert json.loads(written.read_text()) == {"probe.value": 2.5}
        refused = subprocess.run([sys.executable, "-m", "pytest", "-q", "-n2", "--repin", str(module)],
                                 capture_output=True, text=True, cwd=tests.parent)
        assert refused.returncode != 0 and "add -n0" in refused.stdout + refused.stderr
    finally:
        module.unlink()
        written.unlink(missing_ok=True)
