"""The `hitogata body` and `hitogata demo` commands: files, figures, one-line errors."""

import json
from pathlib import Path

import numpy as np
import pytest

from gltf_validator import needs_validator, validate_gltf
from hitogata.cli import main
from hitogata.export.glb_read import read_glb_skin
from hitogata.units import angle, length, mass


def test_body_glb_reloads_with_skin_and_joints(tmp_path: Path, capsys) -> None:
    out = tmp_path / "body.glb"
    assert main(["body", "--sex", "female", "--age", "30", "--stature", "165cm", "--mass", "58kg", "--out", str(out)]) == 0
    line = capsys.readouterr().out
    assert "stature 165.0 cm" in line and "mass 58.0 kg" in line and "BMI 21.3" in line
    skin = read_glb_skin(out)
    assert len(skin.joint_names) == 163 and "upperarm01.L" in skin.joint_names
    assert skin.vertices.shape == (12213, 3) and skin.faces.shape == (24422, 3)
    assert np.ptp(skin.vertices[:, 1]) == pytest.approx(1.65, abs=2e-3)
    assert np.allclose(np.asarray(skin.skin_weights.sum(axis=1)).ravel(), 1.0, atol=1e-6)
    assert skin.extras["stature_cm"] == pytest.approx(165.0, abs=0.2)


def test_same_inputs_same_bytes(tmp_path: Path) -> None:
    args = ["body", "--sex", "male", "--stature", "1.8m", "--mass", "75kg", "--out"]
    for name in ("a.glb", "b.glb", "a.ply", "b.ply", "a.obj", "b.obj"):
        assert main([*args, str(tmp_path / name)]) == 0
    for suffix in ("glb", "ply", "obj"):
        assert (tmp_path / f"a.{suffix}").read_bytes() == (tmp_path / f"b.{suffix}").read_bytes()


@needs_validator
def test_body_glb_passes_khronos_validator(tmp_path: Path) -> None:
    out = tmp_path / "male.glb"
    assert main(["body", "--sex", "male", "--stature", "178cm", "--mass", "78kg", "--out", str(out)]) == 0
    report, _ = validate_gltf(out)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    assert report["info"]["hasSkins"]


@pytest.mark.parametrize(
    "args,message",
    [
        (["--stature", "3m"], "stature 300.0 cm: allowed 140–210 cm"),
        (["--mass=-1kg"], "--mass -1kg: allowed a positive mass, e.g. 58kg"),
        (["--sex", "alien"], "sex 'alien': allowed 'female', 'male'"),
        (["--stature", "165 inches"], "--stature '165 inches': write a number with a unit"),
        (["--stature", "NaN"], "--stature 'NaN': write a number with a unit"),
        (["--mass", "nan kg"], "--mass 'nan kg': write a number with a unit"),
        (["--mass", "200kg"], "mass 200.0 kg at stature 165.0 cm: BMI 73.5, allowed up to 50"),
        (["--age", "nan"], "age nan years: allowed 1..90"),
    ],
)
def test_bad_input_one_line_and_no_file(tmp_path: Path, capsys, args: list[str], message: str) -> None:
    out = tmp_path / "body.glb"
    assert main(["body", *args, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and err.startswith("hitogata: error:") and "\n" not in err
    assert list(tmp_path.iterdir()) == []


def test_unknown_suffix_writes_nothing(tmp_path: Path, capsys) -> None:
    assert main(["body", "--out", str(tmp_path / "body.stl")]) == 2
    assert "allowed: .glb, .obj, .ply" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_demo_writes_default_bodies(tmp_path: Path, capsys, monkeypatch) -> None:
    """The body part of the demo; its dynamics part (≈ 60 s) is tested in test_dynamics_outputs."""
    monkeypatch.setattr("hitogata.commands.demo.run_demo", lambda out, progress: "dynamics: skipped in this test")
    assert main(["demo", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "default female: stature 165.0 cm, mass 62.0 kg" in out
    assert "default male: stature 178.0 cm, mass 78.0 kg" in out
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["male"]["bmi"] == pytest.approx(78.0 / 1.78**2, abs=0.05)
    assert {p.name for p in tmp_path.iterdir()} >= {"default_female.glb", "default_male.obj", "summary.json"}


@pytest.mark.parametrize(
    "text,parse,value",
    [("165cm", length, 1.65), ("1.65m", length, 1.65), ("1650 mm", length, 1.65), ("58kg", mass, 58.0),
     ("58000g", mass, 58.0), ("90deg", angle, np.pi / 2), ("90°", angle, np.pi / 2), ("1.5rad", angle, 1.5)],
)
def test_units_as_a_person_writes_them(text: str, parse, value: float) -> None:
    assert parse(text) == pytest.approx(value, rel=1e-12)


@pytest.mark.parametrize("text", ["165", "165 inches", "1e999m", "cm", "", "5 5cm"])
def test_units_rejected(text: str) -> None:
    from hitogata.errors import HitogataError

    with pytest.raises(HitogataError):
        length(text, "--stature")
