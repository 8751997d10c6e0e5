"""Pressure rows that give their garment: answered by Laplace's law on the rigid tape and by the contact
garment on the soft leg, beside a hand Laplace figure; and the IPC Toolkit's CCD warning kept from users."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from hitogata.validation import load_dataset
from hitogata.validation.answers import answer_dataset
from hitogata.validation.table import compare, pressure_errors, pressure_line

SOURCE = """
[[source]]
id = "tights2001"
authors = "Doe J"
year = 2001
title = "Tights on the default women"
journal = "J Test 1:1-2"
method = "sensor under a stocking of known fabric and reduction factor"
n = 10
subjects = { sex = "female" }
"""

ROW = """
[[row]]
id = "{id}"
source = "tights2001"
kind = "pressure"
where = "table 1"
mean = {mean}
sd = 3.0
unit = "mmHg"
quantity = "{level}"
posture = {{}}
garment = {{ ease = -0.2, fabric_modulus_N_per_m = 400 }}
definition = "interface pressure at the level"
"""

EASE, MODULUS = -0.2, 400.0  # N/m per unit strain
MMHG = 133.322387415


@pytest.mark.slow
def test_a_pressure_row_with_its_garment_is_answered_by_laplace_and_by_the_contact(tmp_path):
    """Two levels of one stocking share one solve; both columns are the hand figure 2π T / C within their
    methods' accuracy."""
    data = tmp_path / "rows.toml"
    data.write_text(SOURCE + ROW.format(id="b", mean=24.0, level="ankle") + ROW.format(id="c", mean=12.0, level="calf"))
    dataset = load_dataset(data)
    answers = answer_dataset(dataset)
    from hitogata.body import Body, default_measurements
    from hitogata.measure.measurements import measure

    stature, mass = default_measurements("female")
    girths = measure(Body.from_measurements("female", 30.0, stature, mass))
    tension = MODULUS * (1.0 / (1.0 + EASE) - 1.0)  # the fabric 25 % longer round than relaxed: 100 N/m
    for got, girth in zip(answers, (girths.ankle_girth, girths.calf_girth)):
        hand = 2 * math.pi * tension / girth / MMHG
        laplace, contact = got.answers["skinned"].value, got.answers["elastic"].value
        assert laplace == pytest.approx(hand, rel=0.01), got.row.id  # the same girth and tension
        # the soft leg's girth shrinks by millimetres under the garment and the fabric lies within the barrier's
        # reach of the skin: the contact's mean round the level is the hand figure within a tenth
        assert contact == pytest.approx(hand, rel=0.1), got.row.id
        assert contact != pytest.approx(laplace, rel=1e-4)  # a solve of its own, not Laplace's figure
    errors = pressure_errors(compare(answers))
    assert errors.rows == 2 and errors.laplace is not None and errors.contact is not None
    assert pressure_line(errors).startswith("Mean |error| on the 2 pressure rows both answer: Laplace ")


def test_a_pressure_row_in_a_posture_has_laplace_only_and_one_without_fabric_neither(tmp_path):
    text = SOURCE + ROW.format(id="seated", mean=14.0, level="calf").replace(
        "posture = {}", 'posture = { "thigh.flexion" = 90, "shank.flexion" = 90 }') \
        + ROW.format(id="bare", mean=14.0, level="calf").replace(
            "garment = { ease = -0.2, fabric_modulus_N_per_m = 400 }", "garment = { ease = -0.2 }")
    (tmp_path / "rows.toml").write_text(text)
    seated, bare = answer_dataset(load_dataset(tmp_path / "rows.toml"), surfaces=("skinned", "elastic"))
    assert seated.answers["skinned"].value is not None and 5.0 < seated.answers["skinned"].value < 30.0
    assert seated.answers["elastic"].value is None and "standing" in seated.answers["elastic"].reason
    assert all(a.value is None and "fabric" in a.reason for a in bare.answers.values())
    assert pressure_errors(compare([seated, bare])).rows == 0
    assert "not measured" in pressure_line(pressure_errors(compare([seated, bare])))


def test_a_step_ccd_allows_no_move_of_is_no_warning_to_the_user(capfd):
    """A garment vertex starting a step within CCD's gap of the skin: no move (the solve's own stuck answer),
    and nothing printed by the IPC Toolkit."""
    import ipctk

    from hitogata.garment.contact.equilibrium import CCD_GAP, _collision_free

    v0 = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.2, 0.2, 0.1 * CCD_GAP], [1.2, 0.2, 0.1 * CCD_GAP],
                   [0.2, 1.2, 0.1 * CCD_GAP]], dtype=float)
    faces = np.array([[0, 1, 2], [3, 4, 5]], dtype=np.int32)
    mesh = ipctk.CollisionMesh(v0, np.asarray(ipctk.edges(faces), dtype=np.int32), faces)
    mesh.can_collide = ipctk.make_vertex_patches_filter(np.array([0, 0, 0, 1, 1, 1], dtype=np.int32))
    v1 = v0.copy()
    v1[3:, 2] -= 0.01
    assert _collision_free(SimpleNamespace(mesh=mesh, ccd=ipctk.AdditiveCCD()), v0, v1) == 0.0
    out, err = capfd.readouterr()
    assert "toi" not in out + err and "Initial distance" not in out + err
