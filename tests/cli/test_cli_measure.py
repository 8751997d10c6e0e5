"""`hitogata measure` and `hitogata body --measure`: the report matches the library's numbers."""

import json
from pathlib import Path

import pytest

from hitogata.body import Body
from hitogata.cli import main
from hitogata.measure import measure


def test_measure_a_body_file(tmp_path: Path, capsys) -> None:
    glb = tmp_path / "body.glb"
    assert main(["body", "--sex", "male", "--stature", "180cm", "--mass", "80kg", "--out", str(glb)]) == 0
    assert main(["measure", str(glb), "--out", str(tmp_path / "report")]) == 0
    printed = capsys.readouterr().out
    report = json.loads((tmp_path / "report" / "measurements.json").read_text())
    expected = measure(Body.from_measurements("male", 30.0, 1.80, 80.0))
    assert "hip girth" in printed and f"{expected.hip_girth * 100:.1f}" in printed
    assert {p.name for p in (tmp_path / "report").iterdir()} == {"measurements.json", "measurements.csv", "measurements.png"}
    assert "waist_girth" in json.dumps(report)
    csv = (tmp_path / "report" / "measurements.csv").read_text()
    assert f"waist_girth,{expected.waist_girth * 100:.2f}" in csv


def test_body_measure_prints_table(tmp_path: Path, capsys) -> None:
    assert main(["body", "--stature", "160cm", "--mass", "55kg", "--out", str(tmp_path / "b.ply"), "--measure"]) == 0
    out = capsys.readouterr().out
    assert "stature                       160.0" in out and "inside leg" in out


@pytest.mark.parametrize("name,content,message", [
    ("missing.glb", None, "no such file"),
    ("body.obj", b"v 0 0 0\n", "no body.json beside it; allowed a .glb written by `hitogata body` or `hitogata pose`, or an .obj/.ply written by `hitogata pose` with its .json"),
])
def test_measure_bad_input(tmp_path: Path, capsys, name: str, content: bytes | None, message: str) -> None:
    path = tmp_path / name
    if content is not None:
        path.write_bytes(content)
    assert main(["measure", str(path), "--out", str(tmp_path / "report")]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "\n" not in err
    assert not (tmp_path / "report").exists()


def test_measure_a_pose_file(tmp_path: Path, capsys) -> None:
    """A `hitogata pose` GLB is measured in its posture: the sleeve path over a bent elbow is longer."""
    glb = tmp_path / "posed.glb"
    assert main(["pose", "--angle", "elbow_r.flexion=120deg", "--out", str(glb)]) == 0
    assert main(["measure", str(glb), "--out", str(tmp_path / "report")]) == 0
    out = capsys.readouterr().out
    row = next(line for line in out.splitlines() if line.startswith("arm length"))
    posed_cm, rest_cm, change = (float(x) for x in row.split()[2:5])
    assert change > 1.0 and posed_cm == pytest.approx(rest_cm + change, abs=0.11)
    names = {p.name for p in (tmp_path / "report").iterdir()}
    assert {"strain_zones.csv", "strain.png"} <= names
    zones = (tmp_path / "report" / "strain_zones.csv").read_text()
    assert "elbow" in zones
