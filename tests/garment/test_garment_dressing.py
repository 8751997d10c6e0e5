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
        # −20 % ease: the fabric 25 % longer round than relaxed on the standing girth, a little more where it
        # lies over the skin's hollows and beside the skin within the barrier's reach, less where the soft
        # leg's girth shrinks under it
        assert 22.0 <= float(row["course_strain_pct"]) < 30.0
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


def test_fit_report_sets_the_contact_beside_laplace_labelled_the_quick_estimate():
    """The fit report's garment section: the contact's mean and peak, Laplace's labelled as the quick
    estimate, the indentation and the girth under the garment where the body was soft (the legging's
    figures on the default female's soft leg)."""
    from hitogata.garment.contact.answers import GarmentContact, LevelContact
    from hitogata.garment.pressure import MMHG
    from hitogata.report.fit_report import contact_section

    mm, cm = 1e-3, 1e-2
    levels = (LevelContact("ankle", 25.8 * MMHG, 24.8 * MMHG, 29.4 * MMHG, 19.00 * cm, 19.30 * cm, 0.270, 0.023, 0.17,
                           0.24 * mm, 1.28 * mm, 18.76 * cm),
              LevelContact("wrist", 22.7 * MMHG, float("nan"), 30.0 * MMHG, 16.0 * cm, 16.2 * cm, 0.12, 0.01, 0.1))
    empty = np.zeros((0, 3))
    contact = GarmentContact("Legging, -20 % ease", levels, empty, empty.astype(int), np.zeros(0), np.zeros(0, bool),
                             empty, empty.astype(int), np.zeros(0), np.zeros(0), "II", 0, False, 3e-4, 60, True)
    html = contact_section(contact)
    assert "Laplace, the quick estimate (mmHg)" in html and "the soft limb" in html
    assert "25.8" in html and "24.8" in html and "0.24 / 1.28" in html and "19.0 → 18.8" in html
    assert "— (rigid body)" in html  # the wrist row has no indentation: not a number
    assert "RAL-GZ 387/1 class at the ankle (B): II" in html


def test_fit_report_refuses_an_unknown_garment_before_any_work(tmp_path, capsys):
    out = tmp_path / "report"
    assert main(["fit-report", "--garment", "no_such_garment", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("hitogata: error:") and "no_such_garment" in err and "legging" in err
    assert "\n" not in err and not out.exists()
