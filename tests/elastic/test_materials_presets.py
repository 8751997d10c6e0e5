"""The shipped materials presets: the calibrated one is what `hitogata identify` finds from the shipped
stiffness rows, every command that builds the elastic body takes `--materials NAME|FILE`, and a mistake in
it is one line before any work."""

from __future__ import annotations

from pathlib import Path

import pytest

from hitogata import cli
from hitogata.motion.scenario import load_scenario
from hitogata.elastic.materials import load_materials, materials_name, shipped_materials
from hitogata.errors import HitogataError
from hitogata.options import DEFAULT_MATERIALS, MATERIALS_PRESETS
from hitogata.validation import load_dataset
from hitogata.validation.identify import identify


def test_every_preset_loads_and_names_itself():
    assert set(shipped_materials()) == set(MATERIALS_PRESETS)
    for name in MATERIALS_PRESETS:
        assert materials_name(load_materials(name)) == name
    assert materials_name(None) == DEFAULT_MATERIALS
    assert load_materials(None).regions == load_materials(DEFAULT_MATERIALS).regions


def test_the_calibrated_preset_is_what_identification_finds_from_the_stiffness_rows():
    literature, calibrated = load_materials("literature"), load_materials("calibrated")
    fit = identify(load_dataset().select((), ("stiffness",)), literature)
    found = fit.materials(literature)
    for region in ("skin", "muscle", "viscera", "bone"):
        assert calibrated.regions[region].E == pytest.approx(found.regions[region].E, rel=1e-4), region
        assert calibrated.regions[region].nu == pytest.approx(found.regions[region].nu, abs=1e-4), region
        assert calibrated.regions[region].rho == pytest.approx(found.regions[region].rho, rel=1e-4), region
    # the rows pin the soft tissue's moduli, each inside the range the literature gives for it (materials.toml:
    # adipose and dermis 1-20 kPa; passive muscle E = 3 x shear modulus 3-45 kPa)
    assert 1e3 < calibrated.regions["skin"].E < 20e3
    assert 3e3 < calibrated.regions["muscle"].E < 45e3
    assert calibrated.regions["muscle"].E != literature.regions["muscle"].E


def mistake(argv: list[str], capsys) -> str:
    """The one line a mistaken command prints (exit 2, no traceback)."""
    try:
        code = cli.main(argv)
    except SystemExit as exit_:
        code = exit_.code
    err = capsys.readouterr().err
    assert code == 2 and "Traceback" not in err, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    return lines[0]


@pytest.mark.parametrize("argv", [
    ["pose", "--materials", "calibrated", "--out", "p.ply"],
    ["ease", "--materials", "calibrated", "--out", "e"],
    ["fit-report", "--materials", "calibrated", "--out", "f"],
], ids=["pose-without-elastic", "ease-on-skinning", "fit-report-on-skinning"])
def test_materials_without_the_elastic_body_is_one_line(tmp_path, monkeypatch, capsys, argv):
    monkeypatch.chdir(tmp_path)
    line = mistake(argv, capsys)
    assert "--materials" in line and "elastic" in line
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("command", [["pose", "--elastic", "--out", "p.ply"], ["ease", "--surface", "elastic"],
                                     ["simulate", "mobility_sit"], ["modes"], ["validate"],
                                     ["dress", "--garment", "legging"]])
def test_an_unknown_preset_is_one_line_naming_the_presets(tmp_path, monkeypatch, capsys, command):
    monkeypatch.chdir(tmp_path)
    line = mistake([*command, "--materials", "calibrate"], capsys)
    assert "calibrate" in line and "calibrated" in line and "literature" in line
    assert list(tmp_path.iterdir()) == []


def test_a_broken_materials_file_is_said_before_the_simulation(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "soft.toml").write_text("[skin]\ndensity = 920\n")

    def refuse(*_, **__):
        raise AssertionError("the model was built before the mistake was found")

    import hitogata.simulation.run as run

    monkeypatch.setattr(run, "build_dynamics", refuse)
    line = mistake(["simulate", "mobility_sit", "--materials", "soft.toml", "--out", "r"], capsys)
    assert line.startswith("hitogata: error: soft.toml:")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["soft.toml"]


SCENARIO = """
[model]
element_size = "60mm"
modes = 4
materials = {materials}
[[keyframe]]
time = "0.5s"
angles = {{ "forearm_l.flexion" = "30deg" }}
"""


def test_a_scenario_names_its_materials_by_preset_or_file_beside_it(tmp_path):
    (tmp_path / "a.toml").write_text(SCENARIO.format(materials='"calibrated"'))
    assert load_scenario(tmp_path / "a.toml").model.materials == "calibrated"
    Path(tmp_path / "mine.toml").write_text(Path(shipped_materials()["calibrated"]).read_text())
    (tmp_path / "b.toml").write_text(SCENARIO.format(materials='"mine.toml"'))
    assert load_scenario(tmp_path / "b.toml").model.materials == str(tmp_path / "mine.toml")
    for bad in ('"/etc/hostname"', '"../mine.toml"'):
        (tmp_path / "c.toml").write_text(SCENARIO.format(materials=bad))
        with pytest.raises(HitogataError, match=r"\[model\]\.materials: .*allowed a path relative"):
            load_scenario(tmp_path / "c.toml")
