"""`hitogata modes` writes frequencies (CSV), mode pictures (PNG), the model (VTU) and a summary."""

import csv
import json

import meshio
import numpy as np
import pytest

from hitogata.cli import main


def test_modes_command_writes_csv_png_vtu(tmp_path, capsys):
    out = tmp_path / "modes"
    code = main(["modes", "--region", "trunk", "--count", "6", "--element-size", "6cm", "--pictures", "2",
                 "--out", str(out)])
    assert code == 0
    printed = capsys.readouterr().out
    assert "6 modes" in printed and "wrote" in printed

    with open(out / "frequencies.csv") as fh:
        rows = list(csv.DictReader(fh))
    f = np.array([float(r["frequency_hz"]) for r in rows])
    assert len(rows) == 6 and np.all(f > 0) and np.all(np.diff(f) >= 0)
    assert all(0 < float(r["damping_ratio"]) < 1 for r in rows)

    for k in (1, 2):
        assert (out / f"mode_{k:02d}.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not (out / "mode_03.png").exists()

    mesh = meshio.read(out / "model.vtu")
    assert mesh.cells[0].type == "tetra10"
    summary = json.loads((out / "summary.json").read_text())
    region = mesh.cell_data["region"][0]
    assert len(region) == summary["elements"] and set(np.unique(region)) == {1, 2, 3}  # bones held, not meshed
    assert summary["region_names"] == ["bone", "viscera", "muscle", "skin"]
    muscle = mesh.cell_data["muscle"][0]
    assert muscle.min() == -1 and muscle.max() < len(summary["muscle_names"])
    soft = [summary["materials"][n]["youngs_modulus_pa"] for n in ("viscera", "muscle", "skin")]
    E = mesh.cell_data["youngs_modulus"][0]  # element means: between the tissues' moduli, mixed at the layers
    assert min(soft) - 1e-6 <= E.min() and E.max() <= max(soft) + 1e-6 and len(np.unique(E)) > 3
    assert summary["dilatation"] == "mean"
    shape = mesh.point_data["mode_01"]
    assert shape.shape == (len(mesh.points), 3)
    fixed = mesh.point_data["fixed"].astype(bool)
    assert fixed.any() and np.all(shape[fixed] == 0)
    assert np.allclose(summary["frequencies_hz"], f, rtol=1e-5)
    # the VTU explains itself to ParaView: frequencies, the names behind the labels, a shape scaled to 3 cm
    assert np.allclose(mesh.field_data["frequencies_hz"], summary["frequencies_hz"])
    assert [k for k in mesh.field_data if k.startswith("region ")] == [
        "region 0: bone", "region 1: viscera", "region 2: muscle", "region 3: skin"]
    assert mesh.field_data["region 2: muscle"].tolist() == [2]
    assert sum(k.startswith("muscle ") for k in mesh.field_data) == len(summary["muscle_names"])
    assert np.linalg.norm(shape, axis=1).max() == pytest.approx(0.03)
    assert mesh.field_data["warp_scale_factor"].tolist() == [1.0]


def test_modes_command_mistakes_are_one_line_and_write_nothing(tmp_path, capsys):
    out = tmp_path / "modes"
    for args in (["--element-size", "25 parsecs"], ["--count", "0"], ["--materials", str(tmp_path / "none.toml")],
                 ["--element-size", "1mm"]):
        assert main(["modes", "--out", str(out), *args]) == 2
        err = capsys.readouterr().err.strip()
        assert err.startswith("hitogata: error:") and "\n" not in err
    assert not out.exists()
