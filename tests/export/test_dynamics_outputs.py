"""What a motion is written as: GLB animation (Khronos validator), VTU series, pictures, GIF, the CLI."""


import json
import re
import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pygltflib as gl
import pytest
from gltf_validator import needs_validator, validate_gltf
from PIL import Image

from hitogata.cli import main
from hitogata.dynamics import BodyDynamics, Keyframe, Timeline, simulate
from hitogata.export import motion_files as files
from hitogata.elastic import build_elastic_model

SCENARIO = """
title = "tiny"
[body]
sex = "female"
[model]
element_size = "60mm"
modes = 6
[time]
duration = "0.4s"
rate = 10
[timeline]
on_limit = "clamp"
[[keyframe]]
time = 0
[[keyframe]]
time = "0.3s"
contractions = { rectus_abdominis_l = "-5%" }
[output]
files = ["glb", "png"]
size = [160, 240]
"""


@pytest.fixture(scope="module")
def motion(female):
    model = build_elastic_model(female, extent="trunk", element_size=60.0, n_modes=8)
    timeline = Timeline.from_keyframes([Keyframe(0.0, {}),
                                        Keyframe(0.4, {("contraction", "rectus_abdominis_l"): -0.06})])
    return simulate(BodyDynamics.build(female, model), timeline, duration=0.6, rate=10, on_limit="clamp")


@needs_validator
def test_glb_animation_is_valid_and_plays_the_frames(tmp_path, motion):
    path = files.write_motion_glb(tmp_path / "m.glb", motion)
    report, _ = validate_gltf(path)
    assert report["issues"]["numErrors"] == 0 and report["issues"]["numWarnings"] == 0
    doc = gl.GLTF2.load_binary(path)
    targets = doc.meshes[0].primitives[0].targets
    assert len(targets) == len(motion.times) and len(doc.animations) == 1
    sampler = doc.animations[0].samplers[0]
    times = doc.accessors[sampler.input]
    assert times.count == len(motion.times) and times.max[0] == pytest.approx(motion.times[-1])
    last = doc.accessors[targets[-1]["POSITION"]]
    moved = np.abs(motion.skin[-1] - motion.dynamics.poser.body.vertices).max(axis=0)
    assert np.allclose(np.maximum(np.abs(last.min), np.abs(last.max)), moved, atol=1e-6)
    # the tissue regions' surfaces, translucent, morph with the same keys
    regions = [m for m in doc.meshes if m.name.startswith("region_")]
    assert sorted(m.name[7:] for m in regions) == ["bone", "muscle", "skin", "viscera"]  # bone: the held capsules
    assert len(doc.animations[0].channels) == 1 + len(regions)
    viscera = next(m for m in regions if m.name == "region_viscera").primitives[0]
    assert doc.materials[viscera.material].alphaMode == "BLEND"
    # each mesh drawn as its name says, smooth, and found by name in three.js (no '.', ':' or spaces)
    for mesh in doc.meshes:
        primitive = mesh.primitives[0]
        assert doc.materials[primitive.material].name == mesh.name and primitive.attributes.NORMAL is not None
    assert doc.materials[doc.meshes[0].primitives[0].material].alphaMode == "BLEND"  # the skin shows the tissue
    assert all(re.fullmatch(r"[A-Za-z0-9_-]+", node.name) for node in doc.nodes)
    surface = files.region_surfaces(motion, light=True)["viscera"]
    assert doc.accessors[viscera.attributes.POSITION].count == len(surface.rest)
    last = doc.accessors[viscera.targets[-1]["POSITION"]]
    moved = np.abs(surface.frame(motion, len(motion.times) - 1) - surface.rest).max(axis=0)
    assert moved.max() > 1e-4 and np.allclose(np.maximum(np.abs(last.min), np.abs(last.max)), moved, atol=1e-6)


def test_vtu_series_reads_back(tmp_path, motion):
    pvd = files.write_pvd(tmp_path, motion)
    steps = ET.parse(pvd).getroot().findall("./Collection/DataSet")
    assert [float(s.get("timestep")) for s in steps] == pytest.approx(motion.times)
    frame = meshio.read(tmp_path / steps[-1].get("file"))
    model = motion.dynamics.model
    assert frame.cells[0].type == "tetra10" and len(frame.cells[0].data) == len(model.elements)
    assert np.allclose(frame.points, motion.nodes[-1], atol=1e-6)
    assert np.array_equal(frame.cell_data["region"][0], model.region)
    assert np.allclose(frame.point_data["displacement"], motion.nodes[-1] - model.points, atol=1e-6)
    assert frame.field_data["time_s"][0] == pytest.approx(motion.times[-1])
    assert frame.field_data["region 1: viscera"].tolist() == [1]  # the names behind the region labels


def not_blank(path) -> bool:
    image = np.asarray(Image.open(path).convert("RGB"), dtype=float)
    return image.std() > 10 and (image < 200).mean() > 0.02


def test_pictures_and_gif_show_something(tmp_path, motion):
    pytest.importorskip("pyvista")
    pngs = files.write_pictures(tmp_path, motion, [0.0, 0.6], ("front", "side"), (160, 240), "m")
    assert [p.name for p in pngs] == ["m_0.00s.png", "m_0.60s.png", "m_elastic.png"]
    assert all(not_blank(p) for p in pngs)
    width, height = Image.open(pngs[0]).size
    assert height == 240 and width >= 300  # two views side by side
    gif = Image.open(files.write_gif(tmp_path / "m.gif", motion, ("front", "side"), (120, 180), rate=5))
    assert gif.n_frames == 4


def test_the_picture_shows_the_tissue_of_the_forearm(motion, female):
    """The regions are drawn over the whole body, whatever the elastic model holds (here the trunk): a point
    of the forearm, beside its bone, is coloured by the translucent tissue, not the background."""
    pytest.importorskip("pyvista")
    from hitogata.render import Points

    rig = female.rig
    i = rig.names.index("lowerarm01.L")
    along = (rig.tails[i] - rig.heads[i]) / np.linalg.norm(rig.tails[i] - rig.heads[i])
    beside = np.array([-along[1], along[0], 0.0]) / np.hypot(along[0], along[1])  # in the front view's plane
    point = 0.5 * (rig.heads[i] + rig.tails[i]) + 0.012 * beside  # inside the forearm, off the skeleton's line
    with files.MotionPictures(motion, ("front",), (300, 450)) as pictures:
        picture = pictures.frame(0, supersample=1)
        marker = pictures._render([Points(pictures.bounds, color="white", size=1.0, opacity=0.0),
                                   Points(point[None], color="blue", radius=0.006)], 0, pictures.size, 1)
    there = (marker[..., 2] > 150) & (marker[..., 0] < 100)
    assert there.sum() >= 4
    red, green, blue = picture[there].astype(float).mean(axis=0)
    print(red, green, blue)
    assert max(red, green, blue) < 245 and red - blue > 15  # the skin's and the bone's tint, not white


def test_simulate_command_writes_files_and_a_summary(tmp_path, capsys):
    pytest.importorskip("pyvista")
    scenario = tmp_path / "tiny.toml"
    scenario.write_text(SCENARIO)
    assert main(["simulate", str(scenario), "--out", str(tmp_path / "out"), "--quiet"]) == 0
    printed = capsys.readouterr().out
    assert "largest skin displacement by the elastic body" in printed and "lowest frequencies" in printed
    out = tmp_path / "out"
    assert (out / "motion.glb").stat().st_size > 0 and (out / "motion_elastic.png").is_file()
    figures = json.loads((out / "motion_summary.json").read_text())
    assert figures["inverted_max"] == 0 and figures["volume_change_max_percent"] < 3
    assert figures["largest_elastic_mm"] > 0.1
    # the whole body (the default extent) stays whole: the summary says so and warns of nothing
    surface = figures["surface"]
    assert surface["folds_beyond_skinning"] == 0 and surface["self_intersections_beyond_skinning"] == 0
    assert surface["below_floor"] == 0 and surface["largest_elastic_m"] * 1e3 == pytest.approx(
        figures["largest_elastic_mm"], rel=1e-5)
    assert "skin surface: 0 folded and 0 crossing" in printed and "WARNING" not in printed


def test_simulate_command_reports_a_bad_scenario_in_one_line(tmp_path, capsys):
    scenario = tmp_path / "bad.toml"
    scenario.write_text(SCENARIO.replace('modes = 6', 'modes = "many"'))
    assert main(["simulate", str(scenario), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "bad.toml: [model].modes" in err
    assert not (tmp_path / "out").exists()


def test_sequence_reads_back_and_measures_over_time(tmp_path, motion, female, capsys):
    path = files.write_sequence(tmp_path / f"m{files.SEQUENCE_SUFFIX}", motion)
    body, arrays = files.read_sequence_body(path)
    assert body.params == female.params
    assert np.array_equal(body.vertices, female.vertices)
    assert arrays["vertices"].shape == (len(motion.times), len(female.vertices), 3)
    assert arrays["joints"].shape == (len(motion.times), len(female.rig.names), 3)
    assert files.find_sequence(tmp_path) == path
    assert main(["measure", str(tmp_path), "--out", str(tmp_path / "report")]) == 0
    rows = (tmp_path / "report" / "measurements_over_time.csv").read_text().splitlines()
    assert len(rows) == 1 + len(motion.times)
    assert "frames; wrote measurements_over_time.csv" in capsys.readouterr().out


def test_measure_rejects_a_folder_without_one_sequence(tmp_path, capsys):
    assert main(["measure", str(tmp_path), "--out", str(tmp_path / "report")]) == 2
    assert "a results folder holds one *_sequence.npz; found none" in capsys.readouterr().err
    assert not (tmp_path / "report").exists()
