"""`import hitogata` is the front door: the pipeline's names, lazily; a posed body measures itself."""

import tomllib
from pathlib import Path

import numpy as np
import pytest

import hitogata
from hitogata.posing import pose_body
from hitogata.measure.landmarks import body_landmarks
from hitogata.posing import poser_for


def test_all_lists_every_export_and_each_resolves_to_its_defining_module() -> None:
    assert sorted(hitogata.__all__, key=str.lower) == sorted(["__version__", *hitogata._EXPORTS], key=str.lower)
    for name, module in hitogata._EXPORTS.items():
        value = getattr(hitogata, name)
        assert value.__module__ == module, name
    pyproject = tomllib.loads((Path(__file__).resolve().parents[2] / "pyproject.toml").read_text())
    assert hitogata.__version__ == pyproject["project"]["version"]
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        hitogata.nothing  # noqa: B018


def test_measure_stays_the_function_after_its_subpackage_is_imported() -> None:
    import hitogata.measure.zones  # noqa: F401  (binds hitogata.measure to the subpackage without the guard)

    assert callable(hitogata.measure) and hitogata.measure.__name__ == "measure"


@pytest.mark.parametrize("sex", ["female", "male"])
def test_a_posed_body_measures_as_its_vertices_and_rig_joints(request, sex: str) -> None:
    body = request.getfixturevalue(sex)
    posed = pose_body(body, clinical={"forearm_r.flexion": np.radians(90), "thigh_l.flexion": np.radians(40)})
    assert posed.rig_joints.shape == (len(body.rig.names), 3)
    assert posed.body is body
    # a joint centre that coincides with a part's joint centre moves with that part exactly
    elbow = body.rig.names.index("lowerarm01.R")
    part = posed.skeleton.joints
    nearest = int(np.argmin(np.linalg.norm(part - body.rig.heads[elbow], axis=1)))
    np.testing.assert_allclose(posed.rig_joints[elbow], posed.joints[nearest], atol=1e-9)
    via_posed = hitogata.measure(posed).as_dict()
    via_arrays = hitogata.measure(body, posed.vertices, posed.rig_joints).as_dict()
    assert via_posed == via_arrays
    assert via_posed["upper_arm_girth"] != hitogata.measure(body).upper_arm_girth
    with pytest.raises(hitogata.HitogataError, match="give the PosedBody alone"):
        hitogata.measure(posed, posed.vertices)


def test_the_per_body_caches_are_the_bodys_own(female, male) -> None:
    assert poser_for(female) is poser_for(female) and poser_for(female) is not poser_for(male)
    assert body_landmarks(female) is body_landmarks(female)
    assert poser_for(female).body is female


@pytest.mark.parametrize("sex, figures", [("female", "stature 165.0 cm, mass 62.0 kg"),
                                          ("male", "stature 178.0 cm, mass 78.0 kg")])
def test_the_command_lines_default_body_is_default_body(tmp_path, capsys, sex: str, figures: str) -> None:
    from hitogata.cli import main

    assert main(["body", "--sex", sex, "--out", str(tmp_path / "b.obj")]) == 0
    assert figures in capsys.readouterr().out


def test_a_view_name_means_one_side_in_every_picture() -> None:
    from hitogata.render.views import VIEWS as RENDER_VIEWS
    from hitogata.report.surface import VIEWS as REPORT_VIEWS

    for name, (_, looking) in REPORT_VIEWS.items():
        np.testing.assert_allclose(looking, RENDER_VIEWS[name].direction, err_msg=name)
