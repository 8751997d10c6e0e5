"""The body files as a user's tools read them: pygltflib (third party) and the Khronos validator.

The body GLB's skin is drawn with a material named "skin" and smooth vertex
normals; every node name survives three.js's loader (no '.', ':', '/', '[',
']' or spaces), with MakeHuman's own name kept in the node's extras; and our
reader still returns the MakeHuman names.
"""

import re

import numpy as np
import pygltflib as gl
import pytest

from gltf_validator import needs_validator, validate_gltf
from hitogata.export.body_files import write_body
from hitogata.export.glb_read import read_glb_skin

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
