"""The output files as a user's tools read them: pygltflib (third party), the Khronos validator, meshio.

The body GLB's skin is drawn with a material named "skin" and smooth vertex
normals; every node name survives three.js's loader (no '.', ':', '/', '[',
']' or spaces), with MakeHuman's own name kept in the node's extras; and our
reader still returns the MakeHuman names. The elastic model's VTU and a
motion's VTU frames carry the tissue at every material sample point and
each region's material, so meshio alone rebuilds the model's element
moduli, Poisson's ratios, densities and tissue fractions.
"""

import os
import re
import subprocess
from pathlib import Path

import meshio
import numpy as np
import pygltflib as gl
import pytest

from gltf_validator import needs_validator, validate_gltf
from hitogata.dynamics import BodyDynamics, Keyframe, Timeline, simulate
from hitogata.export.motion_files import write_motion_glb, write_pvd
from hitogata.elastic import build_elastic_model
from hitogata.export.elastic_files import write_vtu
from hitogata.export.body_files import write_body
from hitogata.export.glb_read import read_glb_skin

SAFE = re.compile(r"[A-Za-z0-9_-]+")
REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def body_glb(tmp_path_factory, male):
    return write_body(tmp_path_factory.mktemp("glb") / "body.glb", male)


def test_the_body_glb_has_a_skin_material_normals_and_safe_names(body_glb, male):
    doc = gl.GLTF2.load_binary(body_glb)
    primitive = doc.meshes[0].primitives[0]
    material = doc.materials[primitive.material]
    assert material.name == "skin" and material.alphaMode == "OPAQUE"
    assert material.pbrMetallicRoughness.metallicFactor == 0.0
    normals = read_glb_skin(body_glb).normals
    assert normals.shape == male.vertices.shape
    assert np.allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-5)
    assert all(SAFE.fullmatch(node.name) for node in doc.nodes)
    renamed = {node.extras["name"]: node.name for node in doc.nodes if "name" in (node.extras or {})}
    assert renamed["upperarm01.L"] == "upperarm01_L" and renamed["hitogata body"] == "hitogata_body"
    assert read_glb_skin(body_glb).joint_names == tuple(male.rig.names)


@needs_validator
def test_the_body_glb_passes_the_khronos_validator(body_glb):
    report, code = validate_gltf(body_glb)
    assert report["issues"]["numErrors"] == 0 and report["issues"]["numWarnings"] == 0, report["issues"]["messages"]
    assert code == 0


def test_the_tape_picture_names_its_tapes(female):
    """measurements.png: a named tape gets its label (text right of the body), an unnamed one none."""
    import io

    from PIL import Image

    from hitogata.measure.measurements import measurement_paths
    from hitogata.report.surface import render_png

    waist = measurement_paths(female)["waist_girth"]

    def pixels(overlays) -> np.ndarray:
        png = render_png(female.vertices, female.faces, ("front",), overlays=overlays)
        return np.asarray(Image.open(io.BytesIO(png)).convert("L"), dtype=int)

    named, plain = pixels({"waist_girth": waist}), pixels((waist,))
    changed = np.abs(named - plain) > 64
    columns = np.flatnonzero(changed.any(axis=0))
    assert changed.sum() > 50 and columns.min() > named.shape[1] // 2  # the label, right of the body's centre


@pytest.fixture(scope="module")
def trunk(female):
    return build_elastic_model(female, extent="trunk", element_size=60.0, n_modes=4)


def rebuilt_tissue(mesh: meshio.Mesh) -> dict[str, np.ndarray]:
    """What a reader computes from the file alone: each element's means over its sample points."""
    samples, weights = mesh.cell_data["region_samples"][0], mesh.field_data["sample_weights"]
    names = [name for name in mesh.field_data if name.startswith("region ")]
    out = {key: mesh.field_data[f"material_{key}"][samples] @ weights
           for key in ("youngs_modulus_pa", "poissons_ratio", "density_kg_m3")}
    for name in names:
        label = int(mesh.field_data[name][0])
        out[name.split(": ")[1]] = (samples == label) @ weights
    return out


def assert_tissue_as_the_model(mesh: meshio.Mesh, model) -> None:
    volume = model.volume
    assert mesh.field_data["sample_barycentric"].shape == (27, 4)
    assert np.array_equal(mesh.cell_data["region_samples"][0], volume.region_samples)
    assert np.array_equal(mesh.cell_data["muscle_samples"][0], volume.muscle_samples)
    tissue = rebuilt_tissue(mesh)
    assert np.allclose(tissue["youngs_modulus_pa"], model.E, rtol=1e-12)
    assert np.allclose(tissue["poissons_ratio"], model.nu, rtol=1e-12)
    assert np.allclose(tissue["density_kg_m3"], model.rho, rtol=1e-12)
    for k, name in enumerate(model.region_names):
        assert np.allclose(tissue[name], volume.region_fractions[:, k], atol=1e-12)
        assert np.allclose(mesh.cell_data[f"fraction_{name}"][0], volume.region_fractions[:, k], atol=1e-12)
    mixed = (volume.region_fractions.max(axis=1) < 1.0 - 1e-9).sum()
    assert mixed == 1277 and len(model.elements) == 1794  # at 60 mm, most elements hold two tissues or more


def test_the_modes_vtu_rebuilds_the_models_materials(tmp_path, trunk):
    mesh = meshio.read(write_vtu(tmp_path / "model.vtu", trunk))
    assert_tissue_as_the_model(mesh, trunk)
    assert np.allclose(mesh.cell_data["youngs_modulus"][0], trunk.E)


@pytest.fixture(scope="module")
def motion(female, trunk):
    timeline = Timeline.from_keyframes([Keyframe(0.0, {}),
                                        Keyframe(0.2, {("contraction", "rectus_abdominis_l"): -0.05})])
    return simulate(BodyDynamics.build(female, trunk), timeline, duration=0.2, rate=10, on_limit="clamp")


def test_a_motion_frame_rebuilds_the_models_materials(tmp_path, motion, trunk):
    write_pvd(tmp_path, motion)
    frame = meshio.read(tmp_path / "motion" / "frame_0002.vtu")
    assert_tissue_as_the_model(frame, trunk)
    assert frame.field_data["muscle 0: " + trunk.muscle_names[0]].tolist() == [0]


@pytest.fixture(scope="module")
def motion_glb(tmp_path_factory, motion):
    return write_motion_glb(tmp_path_factory.mktemp("motion") / "motion.glb", motion)


def accessor(doc: gl.GLTF2, index: int) -> np.ndarray:
    """A float VEC3 accessor's values, read as any glTF reader does (bufferView offset, no stride)."""
    a = doc.accessors[index]
    view = doc.bufferViews[a.bufferView]
    assert a.componentType == gl.FLOAT and a.type == gl.VEC3 and not view.byteStride
    start = (view.byteOffset or 0) + (a.byteOffset or 0)
    return np.frombuffer(doc.binary_blob(), dtype=np.float32, count=3 * a.count, offset=start).reshape(-1, 3)


def test_the_motion_glbs_morph_targets_carry_normals_and_its_time_span(motion_glb, motion):
    """Each frame's target moves the normals too (rest + delta = that frame's own unit vertex normals,
    so three.js lights a moved limb as it lies); the scene's extras hold the animation's time span."""
    from hitogata.geometry.normals import vertex_normals

    doc = gl.GLTF2.load_binary(motion_glb)
    body = motion.dynamics.poser.body
    for mesh in doc.meshes:
        assert all(set(target) == {"POSITION", "NORMAL"} for target in mesh.primitives[0].targets)
    skin = doc.meshes[0].primitives[0]
    rest = accessor(doc, skin.attributes.NORMAL)
    last = rest + accessor(doc, skin.targets[-1]["NORMAL"])
    assert np.allclose(last, vertex_normals(motion.skin[-1].astype(np.float64), body.faces), atol=1e-6)
    assert np.allclose(np.linalg.norm(last, axis=1), 1.0, atol=1e-6)
    turned = np.degrees(np.arccos(np.clip((rest * last).sum(axis=1), -1.0, 1.0)))
    assert turned.max() == pytest.approx(10.745, abs=0.01)  # the contracted rectus turns the skin over it
    assert doc.scenes[doc.scene].extras == {"animation_start_s": 0.0, "animation_end_s": pytest.approx(0.2)}


@needs_validator
def test_the_motion_glb_passes_the_khronos_validator(motion_glb):
    report, code = validate_gltf(motion_glb)
    assert report["issues"]["numErrors"] == 0 and report["issues"]["numWarnings"] == 0, report["issues"]["messages"]
    assert report["info"]["hasMorphTargets"] and code == 0


BLENDER_IMPORT = """
import sys, bpy
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=sys.argv[1])
print(bpy.context.scene.frame_start, bpy.context.scene.frame_end)
"""


@pytest.mark.skipif(not os.environ.get("BLENDER_PYTHON"), reason="set BLENDER_PYTHON to a Python with the bpy wheel")
def test_blender_plays_the_motion_glb_over_its_span_after_the_docs_line(motion_glb):
    """Blender's importer keeps frames 1–250 (it reads no range from a file); the line docs/scenarios.md
    gives sets the scene's range from the scene extras it copied. Runs where the bpy wheel is
    (`BLENDER_PYTHON=/path/to/python-with-bpy`); bpy is no dependency of ours."""
    line = next(line for line in (REPO / "docs" / "scenarios.md").read_text().splitlines()
                if line.startswith("import bpy, math;"))
    script = BLENDER_IMPORT + line + "\nprint(bpy.context.scene.frame_start, bpy.context.scene.frame_end)\n"
    result = subprocess.run([os.environ["BLENDER_PYTHON"], "-c", script, str(motion_glb)],
                            capture_output=True, text=True, timeout=300, check=True)
    ranges = [line for line in result.stdout.splitlines() if re.fullmatch(r"\d+ \d+", line)]
    assert ranges == ["1 250", "0 5"]  # 0.2 s at Blender's 24 fps: frames 0 to 4.8
