"""The shoulder complex reaches overhead through one control; combined limits; limits survive a unit round trip."""

import numpy as np
import pytest

from hitogata.cli import main
from hitogata.errors import HitogataError
from hitogata.posing import poser_for


@pytest.fixture(scope="module", params=["female", "male"])
def poser(request, female, male):
    return poser_for({"female": female, "male": male}[request.param])


def humerus(posed, side):
    sk = posed.skeleton
    shoulder, elbow = posed.joints[sk.index(f"upper_arm_{side}")], posed.joints[sk.index(f"forearm_{side}")]
    d = elbow - shoulder
    return d / np.linalg.norm(d)


@pytest.mark.parametrize("side", ["l", "r"])
@pytest.mark.parametrize("motion", ["flexion", "abduction"])
def test_clinical_180_puts_the_arm_overhead(poser, side, motion):
    """Flexion 180° and abduction 180° through one control each: the humerus points up (within 2°),
    the girdle turned by the scapulohumeral rhythm (60° at full elevation: clavicle 15°, scapula 45°)."""
    posed = poser.pose(clinical={f"shoulder_{side}.{motion}": np.pi})
    d = humerus(posed, side)
    assert np.degrees(np.arccos(d[1])) < 2.0
    clinical = np.degrees(posed.clinical)
    sk = posed.skeleton
    assert clinical[sk.dof_index(f"clavicle_{side}.elevation")] == pytest.approx(15.0, abs=1e-6)
    assert clinical[sk.dof_index(f"scapula_{side}.upward_rotation")] == pytest.approx(45.0, abs=1e-6)


@pytest.mark.parametrize("degrees", [30, 90, 120, 150])
def test_the_control_points_the_arm_in_its_plane(poser, degrees):
    """Intermediate angles: the humerus in the sagittal (flexion) or frontal (abduction) plane at the
    asked elevation (within 2°), the girdle still below 30°."""
    a = np.radians(degrees)
    forward = humerus(poser.pose(clinical={"shoulder_l.flexion": a}), "l")
    hang = humerus(poser.pose(clinical={"shoulder_l.flexion": 0.0}), "l")
    assert np.degrees(np.arccos(forward @ hang)) == pytest.approx(degrees, abs=2.0)
    assert abs(forward[0]) < 0.03 and forward[2] > 0.4
    side = humerus(poser.pose(clinical={"shoulder_l.abduction": a}), "l")
    assert np.degrees(np.arccos(side @ hang)) == pytest.approx(degrees, abs=2.0)
    assert abs(side[2]) < 0.03 and side[0] > 0.4
    q = poser.angles(clinical={"shoulder_l.abduction": np.radians(20)})
    sk = poser.skeleton
    assert q[sk.dof_index("scapula_l.upward_rotation")] == 0.0  # the setting phase: glenohumeral alone


def test_before_the_rhythm_the_glenohumeral_joint_alone_stopped_at_121(poser):
    """The joint's own limit stays: the glenohumeral flexion alone is refused at 180°."""
    with pytest.raises(HitogataError, match=r"upper_arm_l.flexion = 180.0° clinical: allowed -40.0…120.0°"):
        poser.angles(clinical={"upper_arm_l.flexion": np.pi})


def test_combined_limits_refuse_what_the_body_cannot_do(poser):
    # each joint within its own range, together past the vertical into the head: 120 + 50 + 40 = 210°
    too_far = {"upper_arm_l.abduction": 120, "scapula_l.upward_rotation": 50, "clavicle_l.elevation": 40}
    with pytest.raises(HitogataError) as err:
        poser.angles(clinical={k: np.radians(v) for k, v in too_far.items()})
    assert str(err.value) == (
        "shoulder_l.abduction = 210.0° clinical (clavicle_l.elevation + scapula_l.upward_rotation + "
        "upper_arm_l.abduction): the joints together allow at most 180.0°"
    )
    fine = {"upper_arm_l.abduction": 120, "scapula_l.upward_rotation": 50}  # 170°: allowed
    poser.angles(clinical={k: np.radians(v) for k, v in fine.items()})
    with pytest.raises(HitogataError, match=r"shoulder_r.flexion = 190.0° clinical: the shoulder complex allows"):
        poser.angles(clinical={"shoulder_r.flexion": np.radians(190)})
    with pytest.raises(HitogataError, match="upper_arm_l.flexion is set both by shoulder_l and on its own"):
        poser.angles(clinical={"shoulder_l.flexion": 1.0, "upper_arm_l.flexion": 0.5})


def test_a_limit_accepts_its_own_printed_value(poser):
    """lumbar_2.flexion's range shows as -2.3…7.5°: -2.3° (and the shown value of any limit, read
    back in degrees) is accepted and put on the limit, not refused as outside itself."""
    sk = poser.skeleton
    k = sk.dof_index("lumbar_2.flexion")
    for value in (-2.3, -2.3 - 0.04, round(np.degrees(sk.lower[k] + sk.rest[k]), 1)):
        q = poser.angles(clinical={"lumbar_2.flexion": np.radians(value)})
        assert q[k] == sk.lower[k]
    for k, _name in enumerate(sk.dof_names):  # every limit, as shown by --list, round-trips
        for edge in (sk.lower[k], sk.upper[k]):
            shown = round(float(np.degrees(sk.rest[k] + edge)), 1)
            q = np.zeros(sk.n_dofs)
            q[k] = np.radians(shown) - sk.rest[k]
            poser.kinematics.check_limits(q, "raise")
    with pytest.raises(HitogataError, match=r"lumbar_2.flexion = -2.4° clinical: allowed -2.3…7.5°"):
        poser.angles(clinical={"lumbar_2.flexion": np.radians(-2.4)})


def test_cli_poses_the_arm_overhead_with_one_angle(tmp_path, female, monkeypatch, capsys):
    monkeypatch.setattr("hitogata.commands.body_file.body_from_args", lambda args: female)
    assert main(["pose", "--angle", "shoulder_l.flexion=180deg", "--out", str(tmp_path / "up.obj")]) == 0
    out = capsys.readouterr().out
    assert "--angle shoulder_l.flexion 180.0° (shoulder complex): clavicle_l.elevation 0.0° → 15.0°" in out
    assert main(["pose", "--list"]) == 0
    assert "shoulder_l.flexion                         -40.0° …  180.0°" in capsys.readouterr().out
    assert main(["pose", "--angle", "shoulder.abduction=200deg", "--out", str(tmp_path / "x.obj")]) == 2
    assert capsys.readouterr().err.strip().endswith(
        "shoulder_l.abduction = 200.0° clinical: the shoulder complex allows 0.0…180.0°"
    )
    assert not (tmp_path / "x.obj").exists()
