"""The chain on a child: `pose`, `pose --elastic --contact`, `ease` and `fit-report` on the median
6-year-old girl and 14-year-old boy, with the adults' surface checks: no inverted element, no skin
inside another part, no crossing face pair beyond the rest surface's own. Kept small: one elastic
pose per child, ease and the fit report through one motion at 1 frame a second."""

from __future__ import annotations

import json

import numpy as np
import pytest
import trimesh

from hitogata.body import growth
from hitogata.body import Body
from hitogata.cli import main
from hitogata.geometry import self_intersections

pytestmark = pytest.mark.slow  # whole-body meshes and an elastic model per child

CHILDREN = [("female", 6), ("male", 14)]


def crossings(vertices: np.ndarray, faces: np.ndarray) -> set[tuple[int, int]]:
    return set(map(tuple, self_intersections(vertices, faces).tolist()))


@pytest.mark.parametrize("sex, age", CHILDREN)
def test_a_child_poses_skinned_and_elastic_with_contact(tmp_path, capsys, sex, age):
    body = Body.from_measurements(sex, age)
    assert body.stature == pytest.approx(growth.median("stature", float(sex == "male"), age), abs=1e-4)
    rest = crossings(body.vertices, body.faces)
    who = ["--sex", sex, "--age", str(age)]
    angles = ["--angle", "upper_arm_r.flexion=90deg", "--angle", "knee_l.flexion=60deg"]
    skinned = tmp_path / "skinned.ply"
    assert main(["pose", *who, *angles, "--out", str(skinned)]) == 0
    skinned_vertices = trimesh.load(skinned, process=False).vertices
    assert skinned_vertices.shape == body.vertices.shape
    capsys.readouterr()
    elastic = tmp_path / "elastic.ply"
    assert main(["pose", *who, *angles, "--elastic", "--contact", "--out", str(elastic)]) == 0
    printed = capsys.readouterr().out
    assert "inverted    0" in printed and "skin inside another part: 0 vertices" in printed, printed
    posed = trimesh.load(elastic, process=False).vertices
    assert posed.shape == body.vertices.shape and np.isfinite(posed).all()
    # no crossing beyond the rest surface's own (77 at the 6-year-old girl's toes, none at 14)
    assert crossings(posed, body.faces) <= rest
    assert json.loads((tmp_path / "elastic.json").read_text())["surface"] == "elastic"
    assert main(["measure", str(elastic), "--out", str(tmp_path / "m")]) == 0
    zones = json.loads((tmp_path / "m" / "measurements.json").read_text())["zone_strain_percent"]
    assert zones["knee_left"]["stretch_mean"] > 2.0


@pytest.mark.parametrize("sex, age", CHILDREN)
def test_a_childs_ease_and_fit_report_through_sitting(tmp_path, sex, age):
    who = ["--sex", sex, "--age", str(age), "--motions", "sit", "--rate", "1"]
    assert main(["ease", *who, "--out", str(tmp_path / "e")]) == 0
    rows = json.loads((tmp_path / "e" / "ease.json").read_text())["motions"]
    (motion,) = rows
    hip = next(r for r in rows[motion]["largest"] if r["measurement"] == "hip_girth")
    # sitting opens the seat: the hip girth grows, here by 14.9 % (girl, 6) and 6.7 % (boy, 14) of its
    # standing value at 1 frame a second (the median adult woman: 13.9 %); between 3 and 25 % for any child
    assert 0.03 < hip["increase_cm"] / hip["standing_cm"] < 0.25, hip
    assert main(["fit-report", *who, "--out", str(tmp_path / "r")]) == 0
    assert (tmp_path / "r" / "fit_report.html").is_file()
