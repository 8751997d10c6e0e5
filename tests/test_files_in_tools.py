"""The output files as a user's tools read them: pygltflib (third party), the Khronos validator, meshio.

The body GLB's skin is drawn with a material named "skin" and smooth vertex
normals; every node name survives three.js's loader (no '.', ':', '/', '[',
']' or spaces), with MakeHuman's own name kept in the node's extras; and our
reader still returns the MakeHuman names. The elastic model's VTU and a
motion's VTU frames carry the tissue at every material sample point and
each region's material, so meshio alone rebuilds the model's element
moduli, Poisson's ratios, densities and tissue fractions.
"""

import re

import meshio
import numpy as np
import pygltflib as gl
import pytest

from gltf_validator import needs_validator, validate_gltf
from hitogata.dynamics import BodyDynamics, Keyframe, Timeline, simulate
from hitogata.dynamics.files import write_pvd
from hitogata.elastic import build_elastic_model
from hitogata.elastic.files import write_vtu
from hitogata.export.body_files import write_body
from hitogata.export.gltf import read_glb_skin

SAFE = re.compile(r"[A-Za-z0-9_-]+")


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


def test_a_motion_frame_rebuilds_the_models_materials(tmp_path, female, trunk):
    timeline = Timeline.from_keyframes([Keyframe(0.0, {}),
                                        Keyframe(0.2, {("contraction", "rectus_abdominis_l"): -0.05})])
    motion = simulate(BodyDynamics.build(female, trunk), timeline, duration=0.2, rate=10, on_limit="clamp")
    write_pvd(tmp_path, motion)
    frame = meshio.read(tmp_path / "motion" / "frame_0002.vtu")
    assert_tissue_as_the_model(frame, trunk)
    assert frame.field_data["muscle 0: " + trunk.muscle_names[0]].tolist() == [0]
