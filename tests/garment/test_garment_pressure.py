"""Laplace pressure of a stretch garment: analytic sections, fabric files, real bodies at rest and posed."""

from __future__ import annotations

import numpy as np
import pytest
from measure_shapes import circle, ellipse, prism

from hitogata.body import Body
from hitogata.errors import HitogataError
from hitogata.garment import Fabric, Garment, compression_class, garment_pressure, laplace_profile, read_fabric_csv
from hitogata.garment.pressure import MMHG
from hitogata.body.rig import posed_rig_heads
from hitogata.measure.sections import tape_girth
from hitogata.geometry.topology import topology
from hitogata.posing import pose_body

UP = np.array([0.0, 1.0, 0.0])


def section_pressure(outline: np.ndarray, tension: float, window: float):
    v, f = prism(outline, 1.0, rings=3)
    tape = tape_girth(v, topology(f), np.array([0.0, 0.5, 0.0]), UP, np.array([0.0, 0.5, 0.0]))
    return laplace_profile(tape.path, UP, tension, window)


def test_cylinder_pressure_is_tension_over_radius():
    profile, pressure = section_pressure(circle(0.05, 720), 120.0, window=0.01)
    assert np.allclose(pressure, 120.0 / 0.05, rtol=1e-4)
    assert np.sum(pressure) * profile.length / len(pressure) == pytest.approx(2 * np.pi * 120.0, rel=1e-9)


def test_elliptic_cylinder_pressure_follows_the_local_curvature():
    a, b, tension = 0.06, 0.04, 100.0
    profile, pressure = section_pressure(ellipse(a, b, 2000), tension, window=0.002)
    x, z = profile.points[:, 0], -profile.points[:, 2]
    t = np.arctan2(z / b, x / a)
    exact = tension * a * b / (a * a * np.sin(t) ** 2 + b * b * np.cos(t) ** 2) ** 1.5
    assert np.abs(pressure / exact - 1).max() < 0.01
    # the ends of the long axis press (a/b)³ = 3.4 times the flat sides; the mean radius would say 1
    assert pressure.max() / pressure.min() == pytest.approx((a / b) ** 3, rel=0.01)


def test_a_hollow_bridged_by_the_fabric_gets_no_pressure():
    t = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    r = 0.05 * (1 - 0.15 * np.cos(2 * t) ** 8)  # two shallow dents
    _, pressure = section_pressure(np.stack([r * np.cos(t), -r * np.sin(t)], 1), 80.0, window=0.004)
    assert (pressure < 1e-6).sum() > 0.05 * len(pressure)


def test_fabric_curve_from_a_csv_with_units_in_the_header(tmp_path):
    path = tmp_path / "knit.csv"
    path.write_text("# tensile test, course direction\nStrain_%,Tension_N/cm\n10,0.5\n20,1.2\n40,3.0\n")
    fabric = read_fabric_csv(path)
    assert fabric.tension(0.1) == pytest.approx(50.0)
    assert fabric.tension(0.3) == pytest.approx(210.0)
    assert fabric.tension(0.05) == pytest.approx(25.0)  # from (0, 0), added
    assert fabric.tension(0.5) == pytest.approx(390.0)  # the last segment's slope
    assert fabric.tension(-0.1) == 0.0
    path.write_text("strain,tension_N/m\n0,0\n0.5,200\n")
    assert read_fabric_csv(path).tension(0.25) == pytest.approx(100.0)


@pytest.mark.parametrize("text, said", [
    ("strain_%,tension_N/m\n10,abc\n", "line 2: tension_N/m value 'abc'; allowed a finite number"),
    ("strain_%,force_N\n10,5\n", "line 1: header 'strain_%,force_n' has 0 tension columns; allowed exactly one of"),
    ("strain_%,tension_N/m\n10,5\n5,8\n", "line 3: strain '5' is not above the previous line's"),
    ("strain_%,tension_N/m\n10,5\n20\n", "line 3: 1 values; allowed 2"),
    ("strain_%,tension_N/m\n10,-5\n20,3\n", "line 2: value '-5' is negative"),
    ("strain_%,tension_N/m\n10,5\n", "1 data line(s); allowed at least two"),
])
def test_a_malformed_fabric_file_is_one_line_naming_file_line_and_value(tmp_path, text, said):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(HitogataError) as err:
        read_fabric_csv(path)
    message = str(err.value)
    assert message.startswith(f"{path}: ") and said in message and "\n" not in message


def test_garment_input_errors():
    with pytest.raises(HitogataError, match="allowed ankle, calf"):
        Garment(relaxed={"elbow": 0.2})
    with pytest.raises(HitogataError, match="not both or neither"):
        Garment()
    with pytest.raises(HitogataError, match="allowed a finite number > 0"):
        Fabric.linear(-3.0)


@pytest.mark.parametrize("sex, ankle_mmhg", [("female", 17.50), ("male", 14.32)])
def test_pressure_on_the_default_bodies_at_rest(request, sex, ankle_mmhg):
    body = request.getfixturevalue(sex)
    result = garment_pressure(body, Garment(ease=-0.15), Fabric.linear(400.0))
    assert list(result) == ["ankle", "calf", "knee", "thigh", "hip", "waist"]
    for level in result.values():
        assert level.strain == pytest.approx(0.15 / 0.85, rel=1e-9)
        ds = level.profile.length / len(level.pressure)
        assert level.pressure.sum() * ds == pytest.approx(2 * np.pi * level.tension, rel=1e-3)  # force balance
        assert level.peak_pressure > 1.3 * level.mean_pressure  # local curvature, not the equivalent circle
    assert result["ankle"].mean_pressure / MMHG == pytest.approx(ankle_mmhg, abs=0.05)
    # a smaller ankle is pressed harder: pressure decreases up the leg (graduated compression)
    means = [result[k].mean_pressure for k in ("ankle", "calf", "thigh", "hip")]
    assert means == sorted(means, reverse=True)


def test_relaxed_circumferences_and_a_compression_class(female):
    ankle = garment_pressure(female, Garment(relaxed={"ankle": 0.15}), Fabric.linear(400.0))["ankle"]
    tension = 400.0 * (ankle.girth / 0.15 - 1)
    assert ankle.mean_pressure == pytest.approx(2 * np.pi * tension / ankle.girth, rel=1e-9)
    assert compression_class(ankle.mean_pressure) == "II"  # 26.5 mmHg
    assert compression_class(25 * MMHG) == "II" and compression_class(22 * MMHG) == "between classes"
    assert compression_class(10 * MMHG) == "below class I" and compression_class(60 * MMHG) == "IV"


def test_an_extreme_body_is_pressed_everywhere_the_garment_covers():
    body = Body.from_measurements(0.0, 30.0, 1.50, 33.0 * 1.5**2)  # 150 cm, BMI 33
    result = garment_pressure(body, Garment(ease=-0.10), Fabric.linear(300.0))
    assert all(np.isfinite(r.peak_pressure) and r.mean_pressure > 0 for r in result.values())


def test_sitting_stretches_the_knee_thigh_and_seat(male):
    posed = pose_body(male, clinical={"thigh_r.flexion": np.radians(90), "shank_r.flexion": np.radians(90)},
                      skinning="dqs")
    joints = posed_rig_heads(male.rig.heads, posed.skeleton.joints, posed.pose.rotations[0],
                             posed.pose.translations[0])
    garment, fabric = Garment(ease=-0.15), Fabric.linear(400.0)
    rest = garment_pressure(male, garment, fabric)
    sitting = garment_pressure(male, garment, fabric, posed.vertices, joints)
    assert sitting["ankle"].mean_pressure == pytest.approx(rest["ankle"].mean_pressure, rel=1e-6)
    assert sitting["knee"].strain == pytest.approx(0.3433, abs=0.002)
    assert sitting["knee"].peak_pressure > 2 * rest["knee"].peak_pressure
    assert sitting["thigh"].mean_pressure > 1.2 * rest["thigh"].mean_pressure


@pytest.mark.parametrize("sex", ["female", "male"])
def test_the_pressure_map_covers_the_garment_and_nothing_else(request, sex):
    from hitogata.garment.levels import level_planes
    from hitogata.garment.pressure_map import pressure_map
    from hitogata.measure.axes import JointSet

    body = request.getfixturevalue(sex)
    v = body.vertices
    garment, fabric = Garment(ease=-0.15), Fabric.linear(400.0)
    result = pressure_map(body, garment, fabric)
    planes = level_planes(body, v, JointSet(body.rig.names, body.rig.heads))
    between = (v[:, 1] > planes["ankle"][0][1]) & (v[:, 1] < planes["thigh"][0][1] - 0.01)
    right_leg, left_leg = between & (v[:, 0] < -0.02), between & (v[:, 0] > 0.02)
    assert np.isfinite(result.pressure[right_leg]).all() and np.isnan(result.pressure[left_leg]).all()
    assert all(s["strain"] == pytest.approx(0.15 / 0.85, rel=1e-9) for s in result.sections)
    levels = garment_pressure(body, garment, fabric)
    assert np.nanmax(result.pressure) == pytest.approx(max(r.peak_pressure for r in levels.values()), rel=0.05)
    above = v[:, 1] > planes["waist"][0][1] + 0.02
    assert np.isnan(result.pressure[above]).all()
