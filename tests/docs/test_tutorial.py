"""The tutorial's Python runs as written: its blocks, in order, in one namespace, in a temporary
folder — so what docs/tutorial.md shows a newcomer is what the library does."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

TUTORIAL = Path(__file__).resolve().parents[2] / "docs" / "tutorial.md"


def test_the_tutorials_python_runs_and_prints_what_it_says(tmp_path, monkeypatch, capsys):
    blocks = re.findall(r"```python\n(.*?)```", TUTORIAL.read_text(encoding="utf-8"), re.S)
    assert len(blocks) >= 3
    monkeypatch.chdir(tmp_path)
    namespace: dict = {"__name__": "tutorial"}
    for block in blocks:
        exec(compile(block, str(TUTORIAL), "exec"), namespace)
    out = capsys.readouterr().out
    assert "1.65 m, 58.0 kg, BMI 21.3" in out  # the comment the tutorial prints beside the line
    chest, waist, hip = map(float, re.search(r"([\d.]+) ([\d.]+) ([\d.]+) cm", out).groups())
    assert chest > waist and hip > waist
    assert namespace["zones"]["knee_right"].stretch_p95 > 10  # a knee flexed to 60° stretches its skin (%)
    assert namespace["posed"].angle("shank_r.flexion") > 0
    assert (tmp_path / "body.glb").is_file() and (tmp_path / "posed.glb").is_file()
    assert namespace["m"].waist_girth == pytest.approx(0.706, abs=0.002)  # the README's figure for this body
