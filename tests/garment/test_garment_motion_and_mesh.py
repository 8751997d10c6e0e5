"""A dressed garment through a motion (each frame from the last) and a garment given as its rest mesh."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from hitogata.cli import main
from samples import SHORT_GARMENT

SHORT_MOTION = '''title = "knee bend"
[body]
sex = "female"
[model]
extent = "body"
element_size = "40mm"
modes = 30
[time]
duration = "0.4s"
rate = 10
[timeline]
interpolation = "smoothstep"
[[keyframe]]
time = "0s"
[[keyframe]]
time = "0.4s"
clinical = { "shank_r.flexion" = 12 }
'''


@pytest.mark.slow
def test_dress_through_a_motion_writes_each_frame_solved_from_the_last(tmp_path, capsys):
    garment, motion = tmp_path / "sleeve.toml", tmp_path / "bend.toml"
    garment.write_text(SHORT_GARMENT, encoding="utf-8")
    motion.write_text(SHORT_MOTION, encoding="utf-8")
    out = tmp_path / "dressed"
    assert main(["dress", "--garment", str(garment), "--motions", str(motion), "--rate", "5", "--out", str(out)]) == 0
    assert "pressure_motion.csv" in {p.name for p in out.iterdir()}
    standing = {row["level"]: row for row in csv.DictReader((out / "pressure.csv").open(encoding="utf-8"))}
    rows = list(csv.DictReader((out / "pressure_motion.csv").open(encoding="utf-8")))
    assert list(rows[0])[:6] == ["motion", "frame", "time_s", "level", "pressure_mmHg", "peak_mmHg"]
    assert "indentation_mm" in rows[0]
    frames = sorted({int(row["frame"]) for row in rows})
    assert frames == [0, 1, 2]  # 0, 0.2 and 0.4 s at 5 frames a second
    assert [float(row["time_s"]) for row in rows if row["level"] == "ankle"] == pytest.approx([0.0, 0.2, 0.4])
    # every frame started from the last one's equilibrium (the garment and the tissue carried along)
    assert {row["start"] for row in rows} == {"warm"}
    for row in rows:
        level = standing[row["level"]]
        if row["frame"] == "0":  # the motion's first frame is the standing body: the standing answer again,
            # to Newton's tolerance
            assert float(row["pressure_mmHg"]) == pytest.approx(float(level["pressure_mmHg"]), rel=0.01)
            assert float(row["indentation_mm"]) == pytest.approx(float(level["indentation_mm"]), abs=0.05)
        # a 12° knee bend barely moves the ankle and calf's sections: the garment's mean pressure there
        # stays within a tenth of the standing one, the soft leg pressed in by fractions of a millimetre
        assert float(row["pressure_mmHg"]) == pytest.approx(float(level["pressure_mmHg"]), rel=0.1)
        assert -0.5 < float(row["indentation_mm"]) < 1.0
    printed = capsys.readouterr().out
    assert "through bend (3 frames, 3 from the last frame)" in printed


@pytest.mark.slow
def test_the_legging_mesh_presses_as_the_legging_it_was_made_from(female):
    """The shipped mesh garment is the legging sewn for the default female (tools/generate_garment_mesh.py):
    on her it is the same garment, its rings the mesh's sections (the mesh has a ring at every station)."""
    from hitogata.garment.contact import dress_garment

    tube = dress_garment(female, "legging", soft=False)
    mesh = dress_garment(female, "legging_mesh", soft=False)
    assert mesh.converged and mesh.inside == 0 and not mesh.crossing
    for a, b in zip(tube.levels, mesh.levels):
        assert a.level == b.level
        assert b.pressure == pytest.approx(a.pressure, rel=0.03)
        assert b.laplace == pytest.approx(a.laplace, rel=0.03)
        assert b.course_strain == pytest.approx(a.course_strain, abs=0.01)


def _tube_obj(path, rings: int = 4, per_ring: int = 12, closed_end: bool = False, flat: bool = False) -> None:
    angle = 2 * np.pi * np.arange(per_ring) / per_ring
    vertices = [(0.05 * np.cos(a), 0.05 * np.sin(a), 0.1 * j) for j in range(rings) for a in angle]
    faces = []
    for j in range(rings - 1):
        for i in range(per_ring):
            a, b = j * per_ring + i, j * per_ring + (i + 1) % per_ring
            faces += [(a, b, b + per_ring), (a, b + per_ring, a + per_ring)]
    if closed_end:  # a cap over the first opening: a sock's toe, not a tube round the limb
        vertices.append((0.0, 0.0, 0.0))
        faces += [(len(vertices) - 1, (i + 1) % per_ring, i) for i in range(per_ring)]
    if flat:  # a triangle whose corners lie on one line
        vertices += [(0.2, 0.0, 0.0), (0.3, 0.0, 0.0), (0.4, 0.0, 0.0)]
        faces.append((len(vertices) - 3, len(vertices) - 2, len(vertices) - 1))
    lines = [f"v {x} {y} {z}" for x, y, z in vertices] + [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


@pytest.mark.parametrize("shape, says", [
    ({"closed_end": True}, "1 openings"),
    ({"flat": True}, "is degenerate"),
])
def test_a_garment_mesh_not_a_tube_round_the_limb_is_refused(tmp_path, capsys, shape, says):
    _tube_obj(tmp_path / "garment.obj", **shape)
    garment = tmp_path / "garment.toml"
    garment.write_text('segment = "leg"\nmesh = "garment.obj"\n[fabric]\ncourse = "400N/m"\n', encoding="utf-8")
    out = tmp_path / "out"
    assert main(["dress", "--garment", str(garment), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"hitogata: error: {garment}: mesh: garment.obj") and says in err
    assert "allowed" in err and "\n" not in err and not out.exists()


def test_a_garment_mesh_is_read_with_its_relaxed_sections(tmp_path):
    """A straight tube of 12-gons 5 cm round the axis, 30 cm long: its sections' perimeters everywhere."""
    from hitogata.garment.contact.garment_mesh import read_garment_mesh

    _tube_obj(tmp_path / "garment.obj")
    mesh = read_garment_mesh(tmp_path / "garment.obj", "garment.toml: mesh")
    perimeter = 12 * 2 * 0.05 * np.sin(np.pi / 12)
    assert mesh.length == pytest.approx(0.3)
    assert mesh.relaxed(np.linspace(0, 1, 7)) == pytest.approx(np.full(7, perimeter), rel=1e-9)
