"""The README's Python section runs as written: body → pose → elastic model → simulate → measure → files."""

import re
from pathlib import Path

import pytest
from pygltflib import GLTF2

README = Path(__file__).resolve().parents[2] / "README.md"


def first_python_block(text: str, heading: str) -> str:
    section = text[text.index(heading):]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


@pytest.mark.slow
def test_readme_python_chain_runs(tmp_path: Path, monkeypatch, capsys) -> None:
    code = first_python_block(README.read_text(encoding="utf-8"), "## The Python API")
    for step in ("hg.pose_body", "hg.build_elastic_model", "hg.simulate", "hg.measure", "hg.write_motion_glb"):
        assert step in code
    monkeypatch.chdir(tmp_path)
    exec(compile(code, str(README), "exec"), {"__name__": "readme"})
    out = capsys.readouterr().out
    at_rest, posed = map(float, re.search(r"waist ([\d.]+) m at rest, ([\d.]+) m posed", out).groups())
    after = float(re.search(r"waist after the stretch ([\d.]+) m", out).group(1))
    assert at_rest == pytest.approx(0.706, abs=0.0005)  # ISO 8559-1 waist (0.778 at the navel)
    assert posed == pytest.approx(at_rest, abs=0.002)  # arm and knee do not move the waist
    assert after < at_rest  # the stretched rectus pulls the belly in
    assert GLTF2().load(str(tmp_path / "posed.glb")).skins
    assert GLTF2().load(str(tmp_path / "motion.glb")).animations
