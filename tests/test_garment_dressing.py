"""A garment dressed on the default body by `hitogata dress`: the files, the levels' pressures beside
Laplace's, and a mistake refused before any work."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from hitogata.cli import main


@pytest.mark.slow
def test_dress_legging_writes_the_levels_map_and_glb(tmp_path, capsys):
    """The legging on the default female's soft leg: garment and tissue solved together."""
    out = tmp_path / "dressed"
    # 0: converged, no garment vertex inside the soft leg as solved and no triangle through it (exact
    # checks on the tissue's surface after the coupled solve), or nothing is written and the exit is 2
    assert main(["dress", "--garment", "legging", "--out", str(out)]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["dressed.glb", "garment_strain.csv", "pressure.csv",
                                                     "pressure.png", "skin_pressure.csv"]
    rows = {row["level"]: row for row in csv.DictReader((out / "pressure.csv").open(encoding="utf-8"))}
    assert list(rows) == ["ankle", "calf", "knee", "thigh"]
    assert [rows[level]["ral_level"] for level in rows] == ["B", "C", "E", "G"]
    for row in rows.values():
        contact, laplace = float(row["pressure_mmHg"]), float(row["laplace_mmHg"])
        assert float(row["pressure_Pa"]) == pytest.approx(133.322 * contact, rel=1e-3)
        # −20 % ease: the fabric 25 % longer round than relaxed, a little more where it lies over the skin's
        # hollows and beside the skin within the barrier's reach
        assert 25.0 <= float(row["course_strain_pct"]) < 30.0
        # the garment round the body under it (the soft leg pressed in), within the fabric's hollows' bridging
        assert float(row["girth_under_cm"]) < float(row["garment_girth_cm"]) < 1.03 * float(row["girth_cm"])
        # the same tension over the skin's real area and shape: Laplace's mean within a fifth
        assert contact == pytest.approx(laplace, rel=0.2)
        # the soft leg: nearly incompressible tissue (ν 0.49) squeezed all round moves in by fractions of a
        # millimetre on average, up to 1–2 mm where the section is pushed rounder; its girth shrinks by
        # millimetres (a stocking of 20–30 mmHg: calf girth −5 ± 7 mm over 4.5 h, which adds the fluid
        # pressed out: Buhs, Bendick & Glover 1999, J Vasc Surg 30:830)
        assert -0.5 < float(row["indentation_mm"]) < 1.0
        assert 0.3 < float(row["deepest_mm"]) < 5.0
        assert float(row["girth_cm"]) - 1.0 < float(row["girth_under_cm"]) <= float(row["girth_cm"])
    # the thin ankle pressed hardest, the thigh least (the same strain, a larger radius)
    assert float(rows["ankle"]["pressure_mmHg"]) > float(rows["calf"]["pressure_mmHg"]) \
        > float(rows["thigh"]["pressure_mmHg"])
    skin = list(csv.DictReader((out / "skin_pressure.csv").open(encoding="utf-8")))
    assert len(skin) > 500 and max(float(r["pressure_mmHg"]) for r in skin) < 100.0
    printed = capsys.readouterr().out
    assert "RAL-GZ 387/1 class at the ankle (B)" in printed and "on the soft limb" in printed


def test_dress_refuses_a_garment_the_fabric_cannot_stretch_to(tmp_path, capsys):
    garment = tmp_path / "tight.toml"
    garment.write_text('segment = "leg"\nease = "-60%"\n[fabric]\ncourse = "400N/m"\n', encoding="utf-8")
    out = tmp_path / "out"
    assert main(["dress", "--garment", str(garment), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"hitogata: error: {garment}: ease: -60% is smaller than the fabric can stretch to")
    assert "\n" not in err and not out.exists()


@pytest.mark.slow
def test_legging_on_the_largest_body_stays_outside_its_skin():
    """The range's 195 cm BMI 35 male, rigid skin: the rings start clear of a large calf (at 2 mm a ring's
    chord cut it)."""
    from hitogata.body import Body
    from hitogata.garment.contact import dress_garment
    from hitogata.garment.fabric import Fabric

    result = dress_garment(Body.from_measurements("male", stature=1.95, mass=35 * 1.95 ** 2), "legging",
                           soft=False)
    assert result.converged and result.inside == 0 and not result.crossing
    assert 0.0 < result.min_distance < 1e-3
    tension = Fabric.linear(400.0).tension
    for level in result.levels:
        # the mean round a level is the ring's own balance 2π T / C (docs/garment_contact.md)
        balance = 2 * np.pi * float(tension(level.course_strain)) / level.garment_girth
        assert level.pressure == pytest.approx(balance, rel=0.05)
        assert level.peak > level.pressure
