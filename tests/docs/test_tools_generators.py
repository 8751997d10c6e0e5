"""The scripts in tools/ that wrote the shipped skeleton and muscle lists reproduce them byte for byte."""

import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
DATA = REPO / "src" / "hitogata" / "data"


@pytest.mark.parametrize(
    "script,shipped",
    [("generate_skeleton_toml.py", "skeleton.toml"), ("generate_muscles_toml.py", "muscles.toml")],
)
def test_generator_reproduces_the_shipped_file(tmp_path: Path, script: str, shipped: str) -> None:
    out = tmp_path / shipped
    result = subprocess.run(
        [sys.executable, str(REPO / "tools" / script), "--out", str(out)],
        capture_output=True, text=True, timeout=120, check=False,
    )
    assert result.returncode == 0, result.stderr[-2000:]
    assert out.read_bytes() == (DATA / shipped).read_bytes()
