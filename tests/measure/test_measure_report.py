"""Report files for the CLI, and measurements over time."""

import json

import numpy as np
import pytest

from measure_posing import flex_elbow

from hitogata.errors import HitogataError
from hitogata.report.measurements import measure_report, measurement_table
from hitogata.measure.measurements import MEASUREMENT_NAMES, measure, measurement_paths
from hitogata.measure.timeseries import measure_sequence
from hitogata.measure.values import HEIGHTS
from hitogata.report.series import series_csv, write_series
from hitogata.measure.zones import ZONE_NAMES
from hitogata.posing import poser_for
from hitogata.posing.pose import PosedBody

PNG = b"\x89PNG\r\n\x1a\n"


def test_table_lists_every_measurement_in_cm(female):
    rest = measure(female)
    table = measurement_table(rest)
    lines = table.splitlines()
    assert len(lines) == 2 + len(MEASUREMENT_NAMES)
    assert lines[2].split()[-1] == "165.0"  # stature
    compared = measurement_table(rest, rest)
    assert "rest cm" in compared and compared.splitlines()[3].endswith("+0.0")


def test_rest_report_writes_measurements_and_picture(female, tmp_path):
    report = measure_report(female, tmp_path)
    written = report.files
    assert report.rest is None
    np.testing.assert_equal(report.measurements.as_dict(), measure(female).as_dict())  # the table's figures
    assert set(written) == {"json", "csv", "picture"}
    document = json.loads(written["json"].read_text())
    assert document["units"] == "m"
    assert document["measurements"]["stature"] == pytest.approx(1.65, abs=1e-9)
    assert set(document["landmarks_m"]) >= {"cervicale", "acromion_right", "crotch"}
    rows = written["csv"].read_text().splitlines()
    assert rows[0] == "measurement,value_cm" and len(rows) == 1 + len(MEASUREMENT_NAMES)
    assert written["picture"].read_bytes().startswith(PNG)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(p.name for p in written.values())  # no temporaries
    # every tape is drawn: all but the heights, which have no path on the skin
    assert set(measurement_paths(female)) == set(MEASUREMENT_NAMES) - set(HEIGHTS)


def test_posed_report_adds_zone_strain_and_heat_map(female, tmp_path):
    vertices, joints = flex_elbow(female, np.radians(120))
    report = measure_report(female, tmp_path, vertices, joints, title="right elbow 120°")
    written = report.files
    assert report.rest is not None
    np.testing.assert_equal(report.rest.as_dict(), measure(female).as_dict())
    np.testing.assert_equal(report.measurements.as_dict(), measure(female, vertices, joints).as_dict())
    assert written["strain"].read_bytes().startswith(PNG)
    zones = written["zones"].read_text().splitlines()
    assert zones[0].startswith("zone,stretch_mean_pct") and len(zones) == 1 + len(ZONE_NAMES)
    document = json.loads(written["json"].read_text())
    assert document["zone_strain_percent"]["elbow_right"]["stretch_max"] > 30
    assert document["measurements"]["arm_length"] > document["rest_measurements"]["arm_length"]


def test_report_needs_an_existing_directory(female, tmp_path):
    with pytest.raises(HitogataError, match="not a directory"):
        measure_report(female, tmp_path / "missing")


def test_sequence_gives_one_row_per_frame(female, tmp_path):
    angles = np.radians([40.0, 80.0, 120.0])
    frames = [flex_elbow(female, a) for a in angles]
    times = np.array([0.0, 0.5, 1.0])
    series = measure_sequence(female, times, [f[0] for f in frames], [f[1] for f in frames])
    assert series.values.shape == (3, len(MEASUREMENT_NAMES))
    arm = series.values[:, MEASUREMENT_NAMES.index("arm_length")]
    assert np.all(np.diff(arm) > 0)  # the arm length grows as the elbow bends
    elbow = series.zone_stretch[:, ZONE_NAMES.index("elbow_right")]
    assert np.all(np.diff(elbow) > 0)
    csv = series_csv(series).splitlines()
    assert csv[0].startswith("time_s,stature_cm,") and "elbow_right_stretch_pct" in csv[0]
    assert len(csv) == 4 and csv[1].startswith("0,165,")
    written = write_series(series, tmp_path, title="elbow flexion")
    assert written["plot"].read_bytes().startswith(PNG)
    assert written["csv"].read_text() == series_csv(series)


def test_sequence_checks_its_input(female):
    v, j = female.vertices, female.rig.heads
    with pytest.raises(HitogataError, match="times"):
        measure_sequence(female, [0.0, 0.0], [v, v], [j, j])
    with pytest.raises(HitogataError, match="2 times, 1 vertex frames"):
        measure_sequence(female, [0.0, 1.0], [v], [j, j])
    with pytest.raises(HitogataError, match="measurement 'girth'"):
        measure_sequence(female, [0.0], [v], [j], names=("girth",))
    with pytest.raises(HitogataError, match="vertices: row 3"):
        broken = v.copy()
        broken[3] = np.inf
        measure_sequence(female, [0.0], [broken], [j])


@pytest.mark.parametrize("sex", ["female", "male"])
def test_the_knee_girth_is_undefined_where_its_plane_runs_along_the_limbs(request, sex, tmp_path):
    """Standing and at 90° the knee girth's plane cuts the knee; in a deep squat (knee 130°) it runs along the
    thigh and the calf (docs/measurements.md): undefined, and the report says so, never NaN or a number."""
    body = request.getfixturevalue(sex)
    poser = poser_for(body)

    def knee(hip: float, knee: float) -> PosedBody:
        return poser.pose(clinical={f"{part}_{side}.flexion": np.radians(angle) for side in "lr"
                                    for part, angle in (("thigh", hip), ("shank", knee))}, skinning="dqs")

    assert np.isfinite(measure(body).knee_girth) and np.isfinite(measure(knee(90, 90)).knee_girth)
    squat = knee(115, 130)
    assert np.isnan(measure(squat).knee_girth)
    report = measure_report(body, tmp_path, squat.vertices, squat.rig_joints)
    assert "knee_girth,undefined" in report.files["csv"].read_text().splitlines()
    document = json.loads(report.files["json"].read_text())
    assert document["measurements"]["knee_girth"] is None and "thigh and the calf" in document["undefined"]["knee_girth"]
    line = next(row for row in measurement_table(report.measurements, report.rest).splitlines() if "knee" in row)
    assert line.split()[-3:] == ["undefined", f"{report.rest.knee_girth * 100:.1f}", "undefined"]
    series = measure_sequence(body, np.array([0.0, 1.0]), [body.vertices, squat.vertices],
                              [body.rig.heads, squat.rig_joints])
    rows = [row.split(",") for row in series_csv(series).splitlines()]
    column = rows[0].index("knee_girth_cm")
    assert rows[1][column] == f"{measure(body).knee_girth * 100:.6g}" and rows[2][column] == "undefined"
