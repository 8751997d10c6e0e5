"""The two legs' combined limit: a hip adducts past the midline only with the other leg out of the way
(`hitogata.skeleton.combined`, measured in its docstring and docs/posing.md)."""

import numpy as np
import pytest

from hitogata.cli import main
from hitogata.errors import HitogataError
from hitogata.muscles.activation import MuscleLimitWarning
from hitogata.posing import poser_for

D = np.radians
OLD_POSE = "hips.abduction (both legs) = -24.0° clinical (thigh_l.abduction + thigh_r.abduction): the joints together " \
           "allow at least 0.0° with thigh_l.flexion and thigh_r.flexion 0.0° apart (0.0° up to 30° apart, 0.33° " \
           "less per degree beyond)"


@pytest.fixture(scope="module", params=["female", "male"])
def poser(request, female, male):
    return poser_for({"female": female, "male": male}[request.param])


def hips(poser, q):
    sk = poser.skeleton
    return np.degrees(sk.clinical(q)[[sk.dof_index("thigh_l.abduction"), sk.dof_index("thigh_r.abduction")]])


def test_one_hip_adducted_30_with_the_other_leg_at_rest_is_refused(poser):
    """The issue's old pose: the left leg swung 30° across the straight right one (at rest, 6°) goes
    through it, bones included."""
    with pytest.raises(HitogataError) as err:
        poser.angles(clinical={"thigh_l.abduction": D(-30)})
    assert str(err.value) == OLD_POSE


def test_the_aaos_pose_is_accepted(poser):
    """AAOS: hip adduction 30° with the other leg abducted out of the way (30°)."""
    q = poser.angles(clinical={"thigh_l.abduction": D(-30), "thigh_r.abduction": D(30)})
    assert hips(poser, q) == pytest.approx([-30.0, 30.0], abs=1e-9)


def test_a_leg_flexed_ahead_has_room_to_adduct(poser):
    """Past 30° of flexion apart, a third of a degree of adduction per degree: at left hip flexion 90°
    (the right at rest, 5°: 85° apart) the legs together may reach -18.3°."""
    poser.angles(clinical={"thigh_l.flexion": D(90), "thigh_l.abduction": D(-24.3)})  # -24.3 + 6 = -18.3
    with pytest.raises(HitogataError, match=r"= -19.0° clinical .* at least -18.3° with thigh_l.flexion and "
                                            r"thigh_r.flexion 85.0° apart"):
        poser.angles(clinical={"thigh_l.flexion": D(90), "thigh_l.abduction": D(-25)})


def test_clamp_shares_the_excess_between_the_hips(poser):
    with pytest.warns(MuscleLimitWarning, match=r"hips.abduction \(both legs\)"):
        q = poser.angles(clinical={"thigh_l.abduction": D(-30)}, on_limit="clamp")
    assert hips(poser, q) == pytest.approx([-18.0, 18.0], abs=1e-9)  # -24° shared: +12° each
    both = {"thigh_l.abduction": D(-20), "thigh_r.abduction": D(-20)}
    with pytest.warns(MuscleLimitWarning):
        q = poser.angles(clinical=both, on_limit="clamp")
    assert hips(poser, q) == pytest.approx([0.0, 0.0], abs=1e-9)
    # the flexions are not moved: the bound at these flexions is met by the abductions alone
    with pytest.warns(MuscleLimitWarning):
        q = poser.angles(clinical={"thigh_l.flexion": D(90), "thigh_l.abduction": D(-30)}, on_limit="clamp")
    sk = poser.skeleton
    assert np.degrees(sk.clinical(q)[sk.dof_index("thigh_l.flexion")]) == pytest.approx(90.0)
    assert hips(poser, q).sum() == pytest.approx(-85.0 / 3 + 10.0, abs=1e-9)


def test_cli_refuses_the_old_pose_with_the_line(tmp_path, female, monkeypatch, capsys):
    monkeypatch.setattr("hitogata.commands.body_file.body_from_args", lambda args: female)
    assert main(["pose", "--angle", "thigh_l.abduction=-30deg", "--out", str(tmp_path / "x.obj")]) == 2
    assert capsys.readouterr().err.strip().endswith(OLD_POSE)
    assert not (tmp_path / "x.obj").exists()
    assert main(["pose", "--angle", "thigh_l.abduction=-30deg", "--angle", "thigh_r.abduction=30deg",
                 "--out", str(tmp_path / "aaos.obj")]) == 0
    assert (tmp_path / "aaos.obj").exists()
