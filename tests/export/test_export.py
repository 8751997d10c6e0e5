"""Tests for hitogata.export: skinned GLB round trip and validity, mesh files, atomic writes."""

import os
from pathlib import Path

import numpy as np
import pytest
import trimesh
from scipy import sparse

from hitogata.errors import HitogataError
from hitogata.export import atomic, read_glb_skin, write_glb, write_mesh

from gltf_validator import needs_validator, validate_gltf

JOINT_NAMES = ["root", "mid", "tip", "end", "prop"]
JOINT_PARENTS = np.array([-1, 0, 1, 2, -1])
JOINT_POSITIONS = np.array([[0, 0, 0], [0, 0.33, 0], [0, 0.66, 0], [0, 1.0, 0], [0.3, 0.5, 0.1]])


@pytest.fixture(scope="module")
def rig() -> dict:
    """A 1 m upright cylinder with a 4-joint chain plus a second root, and smooth weights.

    Most vertices have 5 influences (so top-4 truncation matters); the bottom
    cap has 1 and the top cap 2 (so there are empty slots).
    """
    mesh = trimesh.creation.cylinder(radius=0.05, height=1.0, sections=16).subdivide_to_size(0.1)
    mesh.apply_transform(trimesh.transformations.rotation_matrix(-np.pi / 2, [1, 0, 0]))
    mesh.apply_translation([0, 0.5, 0])
    y = mesh.vertices[:, 1]
    weights = np.exp(-(((y[:, None] - JOINT_POSITIONS[:4, 1]) / 0.2) ** 2))
    weights = np.hstack([weights, np.full((len(y), 1), 0.02)])
    weights[y < 0.01] = [1, 0, 0, 0, 0]
    weights[y > 0.99] = [0, 0, 0.3, 0.7, 0]
    weights /= weights.sum(axis=1, keepdims=True)
    return {
        "vertices": mesh.vertices,
        "faces": mesh.faces,
        "joint_names": JOINT_NAMES,
        "joint_parents": JOINT_PARENTS,
        "joint_positions": JOINT_POSITIONS,
        "skin_weights": weights,
    }


def write(path: Path, rig: dict, **overrides) -> Path:
    args = {**rig, **overrides}
    return write_glb(path, args.pop("vertices"), args.pop("faces"), **args)


def top4(weights: np.ndarray) -> np.ndarray:
    """Reference truncation: zero all but each row's 4 largest weights, renormalise."""
    out = np.zeros_like(weights)
    for v, row in enumerate(weights):
        keep = np.argsort(-row, kind="stable")[:4]
        out[v, keep] = row[keep]
    return out / out.sum(axis=1, keepdims=True)


# --------------------------------------------------------------------------- GLB


def test_glb_round_trip(tmp_path, rig):
    path = write(tmp_path / "body.glb", rig, extras={"stature": 1.65})
    back = read_glb_skin(path)
    assert np.allclose(back.vertices, rig["vertices"], atol=1e-7)
    assert np.array_equal(back.faces, rig["faces"])
    assert back.joint_names == tuple(JOINT_NAMES)
    assert np.array_equal(back.joint_parents, JOINT_PARENTS)
    assert np.allclose(back.joint_positions, JOINT_POSITIONS, atol=1e-6)
    assert back.extras == {"stature": 1.65}
    assert np.allclose(np.linalg.norm(back.normals, axis=1), 1.0, atol=1e-6)
    assert np.allclose(back.skin_weights.toarray(), top4(rig["skin_weights"]), atol=1e-6)
    assert back.skin_weights.getnnz(axis=1).max() == 4


def test_empty_slots_point_at_joint_zero_and_rows_sum_to_one(rig):
    from hitogata.export.gltf import limit_influences

    joints, weights = limit_influences(rig["skin_weights"], rig["skin_weights"].shape)
    assert joints.dtype == np.uint16 and weights.dtype == np.float32
    assert np.all(joints[weights == 0] == 0)
    assert (weights == 0).any()
    assert np.all(np.abs(weights.astype(np.float64).sum(axis=1) - 1) < 1e-7)
    assert np.all(np.diff(weights, axis=1) <= 0)  # largest first


def test_computed_normals_are_area_weighted_radial(tmp_path):
    sphere = trimesh.creation.icosphere(subdivisions=2)
    weights = np.ones((len(sphere.vertices), 1))
    path = write_glb(
        tmp_path / "ball.glb", sphere.vertices, sphere.faces,
        joint_names=["root"], joint_parents=[-1], joint_positions=[[0, 0, 0]], skin_weights=weights,
    )
    normals = read_glb_skin(path).normals
    expected = np.zeros((len(sphere.vertices), 3))
    for face in sphere.faces:
        a, b, c = sphere.vertices[face]
        expected[face] += np.cross(b - a, c - a)  # twice the area times the unit normal
    expected /= np.linalg.norm(expected, axis=1, keepdims=True)
    assert np.allclose(normals, expected, atol=1e-6)
    assert np.all(np.einsum("ij,ij->i", normals, sphere.vertices) > 0.99)  # outward, near radial


def test_bytes_are_deterministic_and_independent_of_weight_format(tmp_path, rig):
    a = write(tmp_path / "a.glb", rig).read_bytes()
    b = write(tmp_path / "b.glb", rig).read_bytes()
    c = write(tmp_path / "c.glb", rig, skin_weights=sparse.csr_matrix(rig["skin_weights"])).read_bytes()
    assert a == b == c


def test_failing_write_leaves_no_file(tmp_path, rig, monkeypatch):
    target = tmp_path / "body.glb"

    def broken_replace(src, dst):
        raise OSError("disk full (simulated)")

    monkeypatch.setattr(atomic.os, "replace", broken_replace)
    with pytest.raises(OSError, match="simulated"):
        write(target, rig)
    assert list(tmp_path.iterdir()) == []


def test_failing_write_keeps_the_old_file(tmp_path, rig, monkeypatch):
    target = write(tmp_path / "body.glb", rig)
    before = target.read_bytes()
    bad = rig["vertices"].copy()
    bad[3, 1] = np.nan
    with pytest.raises(HitogataError, match="vertices"):
        write(target, rig, vertices=bad)
    monkeypatch.setattr(atomic.os, "replace", lambda src, dst: (_ for _ in ()).throw(OSError("simulated")))
    with pytest.raises(OSError):
        write(target, rig, extras={"changed": True})
    assert target.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["body.glb"]


@pytest.mark.parametrize(
    ("override", "message"),
    [
        ({"joint_parents": np.array([1, 0, 1, 2, -1])}, "cycle"),
        ({"joint_parents": np.array([-1, 0, 1, 2])}, "joint_parents"),
        ({"joint_names": ["a", "a", "b", "c", "d"]}, "duplicates"),
        ({"skin_weights": np.zeros((1, 5))}, "skin_weights: shape"),
        ({"faces": np.array([[0, 1, 10_000]])}, "faces"),
    ],
)
def test_bad_inputs_raise_one_line_errors(tmp_path, rig, override, message):
    with pytest.raises(HitogataError, match=message) as caught:
        write(tmp_path / "x.glb", rig, **override)
    assert "\n" not in str(caught.value)
    assert not (tmp_path / "x.glb").exists()


def test_unbound_vertex_is_named(tmp_path, rig):
    weights = rig["skin_weights"].copy()
    weights[7] = 0
    with pytest.raises(HitogataError, match="vertex 7"):
        write(tmp_path / "x.glb", rig, skin_weights=weights)


def test_write_glb_rejects_other_suffixes(tmp_path, rig):
    with pytest.raises(HitogataError, match=r"body\.gltf.*\.glb"):
        write(tmp_path / "body.gltf", rig)


@needs_validator
def test_khronos_validator_reports_no_errors(tmp_path, rig):
    path = write(tmp_path / "body.glb", rig, extras={"stature": 1.65})
    report, returncode = validate_gltf(path)
    issues = report["issues"]
    assert issues["numErrors"] == 0, issues["messages"]
    assert issues["numWarnings"] == 0, issues["messages"]
    assert report["info"]["hasSkins"] and report["info"]["maxInfluences"] == 4
    assert returncode == 0


# --------------------------------------------------------------------------- plain mesh files


@pytest.mark.parametrize("suffix", [".obj", ".ply", ".glb"])
def test_mesh_files_round_trip(tmp_path, suffix):
    box = trimesh.creation.box(extents=(0.3, 1.7, 0.2))
    path = write_mesh(tmp_path / f"body{suffix}", box.vertices, box.faces)
    back = trimesh.load(path, force="mesh", process=False)
    assert np.allclose(back.vertices, box.vertices, atol=1e-6)
    assert np.array_equal(back.faces, box.faces)
    assert [p.name for p in tmp_path.iterdir()] == [path.name]


def test_unknown_mesh_suffix_is_a_one_line_error(tmp_path):
    with pytest.raises(HitogataError) as caught:
        write_mesh(tmp_path / "body.stl", np.zeros((3, 3)), [[0, 1, 2]])
    message = str(caught.value)
    assert "body.stl" in message and ".glb, .obj, .ply" in message and "\n" not in message
    assert not (tmp_path / "body.stl").exists()


def test_missing_directory_is_a_clear_error(tmp_path):
    with pytest.raises(HitogataError, match="does not exist"):
        write_mesh(tmp_path / "nowhere" / "body.obj", np.eye(3), [[0, 1, 2]])
    assert os.listdir(tmp_path) == []
