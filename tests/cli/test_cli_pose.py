"""`hitogata pose`: a re-posable GLB on the 65-part skeleton, the posed surface, one-line errors."""

from pathlib import Path

import numpy as np
import pygltflib as gl
import pytest

from gltf_validator import needs_validator, validate_gltf
from hitogata.body import Body
from hitogata.cli import main
from hitogata.export.glb_read import read_glb_skin
from hitogata.posing import Poser, poser_for
from hitogata.skeleton.spec import load_skeleton_spec


def quaternion_matrix(q) -> np.ndarray:
    x, y, z, w = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def joint_world_matrices(path: Path) -> np.ndarray:
    """(J, 4, 4) world matrices of the skin's joints, composed from the nodes' TRS as a viewer does."""
    doc = gl.GLTF2.load_binary(path)
    parent = {c: p for p, node in enumerate(doc.nodes) for c in node.children or []}

    def world(n: int) -> np.ndarray:
        node, local = doc.nodes[n], np.eye(4)
        local[:3, 3] = node.translation or (0.0, 0.0, 0.0)
        if node.rotation:
            local[:3, :3] = quaternion_matrix(node.rotation)
        return world(parent[n]) @ local if n in parent else local

    return np.array([world(n) for n in doc.skins[0].joints])


def viewer_skinning(path: Path) -> np.ndarray:
    """The posed surface a glTF viewer shows: linear blend skinning with the file's joints and weights."""
    skin = read_glb_skin(path)
    inverse_bind = np.tile(np.eye(4), (len(skin.joint_names), 1, 1))
    inverse_bind[:, :3, 3] = -skin.joint_positions
    joint = joint_world_matrices(path) @ inverse_bind
    homogeneous = np.c_[skin.vertices, np.ones(len(skin.vertices))]
    return np.einsum("vj,jab,vb->va", skin.skin_weights.toarray(), joint, homogeneous)[:, :3]


@pytest.fixture()
def female_args(female: Body, monkeypatch):
    """The CLI's body is the session's default female (saves building one per call)."""
    monkeypatch.setattr("hitogata.commands.body_file.body_from_args", lambda args: female)
    return female


def test_glb_carries_the_skeleton_and_the_requested_pose(tmp_path: Path, capsys) -> None:
    out = tmp_path / "posed.glb"
    args = ["pose", "--sex", "female", "--stature", "165cm", "--mass", "60kg",
            "--angle", "elbow_l.flexion=90deg", "--muscle", "biceps_brachii_r=25%", "--out", str(out)]
    assert main(args) == 0
    printed = capsys.readouterr().out
    assert "65-part skeleton, 2 joint angles moved" in printed
    assert "--angle forearm_l.flexion" in printed and "→ 90.0°" in printed
    assert "biceps_brachii_r contracted 25.0%: forearm_r.flexion" in printed

    skin = read_glb_skin(out)
    spec = load_skeleton_spec()
    assert skin.joint_names == spec.names and len(skin.joint_names) == 65
    assert np.array_equal(skin.joint_parents, np.array(spec.parents))
    assert np.allclose(np.asarray(skin.skin_weights.sum(axis=1)).ravel(), 1.0, atol=1e-6)
    assert skin.extras["clinical_angles_deg"]["forearm_l.flexion"] == pytest.approx(90.0)

    # The elbow in the file, measured as a viewer poses it: the angle between upper arm and forearm.
    joints = joint_world_matrices(out)[:, :3, 3]
    i = {name: k for k, name in enumerate(skin.joint_names)}
    upper = joints[i["forearm_l"]] - joints[i["upper_arm_l"]]
    fore = joints[i["hand_l"]] - joints[i["forearm_l"]]
    bend = np.degrees(np.arccos(upper @ fore / np.linalg.norm(upper) / np.linalg.norm(fore)))
    assert bend == pytest.approx(90.0, abs=0.01)

    # What a viewer shows is hitogata's own LBS surface, to a fraction of a millimetre (4 weights per vertex).
    body = Body.from_measurements(sex="female", age=30, stature=1.65, mass=60.0)
    ours = Poser.from_body(body).pose(
        contractions={"biceps_brachii_r": 0.25}, clinical={"forearm_l.flexion": np.pi / 2}
    ).vertices
    assert np.abs(skin.vertices - body.vertices).max() < 1e-6  # the file's mesh is the rest skin
    assert np.linalg.norm(viewer_skinning(out) - ours, axis=1).max() < 1e-3


@needs_validator
def test_posed_glb_passes_khronos_validator(tmp_path: Path, female_args) -> None:
    out = tmp_path / "posed.glb"
    assert main(["pose", "--muscle", "rectus_abdominis=-10%", "--angle", "knee.flexion=60deg", "--out", str(out)]) == 0
    report, _ = validate_gltf(out)
    assert report["issues"]["numErrors"] == 0 and report["issues"]["numWarnings"] == 0, report["issues"]["messages"]
    assert report["info"]["hasSkins"]


def test_obj_is_the_posed_surface_with_dqs(tmp_path: Path, female_args, capsys) -> None:
    out = tmp_path / "posed.obj"
    assert main(["pose", "--muscle", "pronator_teres_l=0.02", "--skinning", "dqs", "--out", str(out)]) == 0
    vertices = np.array([line.split()[1:4] for line in out.read_text().splitlines() if line.startswith("v ")], float)
    expected = poser_for(female_args).pose(contractions={"pronator_teres_l": 0.02}, skinning="dqs").vertices
    assert np.abs(vertices - expected).max() < 1e-6
    assert "pronator_teres_l contracted 2.0%: forearm_l.pronation" in capsys.readouterr().out


def test_side_less_names_move_both_sides(tmp_path: Path, female_args) -> None:
    out = tmp_path / "posed.glb"
    assert main(["pose", "--muscle", "biceps_brachii=20%", "--muscle", "rectus_abdominis=-5%",
                 "--angle", "knee.flexion=30deg", "--out", str(out)]) == 0
    angles = read_glb_skin(out).extras["clinical_angles_deg"]
    assert angles["forearm_l.flexion"] == pytest.approx(angles["forearm_r.flexion"]) and angles["forearm_l.flexion"] > 45
    assert angles["shank_l.flexion"] == angles["shank_r.flexion"] == pytest.approx(30.0)
    assert angles["lumbar_3.flexion"] < 0  # stretched: extension


def test_clamp_notes_and_writes(tmp_path: Path, female_args, capsys) -> None:
    out = tmp_path / "posed.ply"
    assert main(["pose", "--muscle", "biceps_brachii_l=0.9", "--on-limit", "clamp", "--out", str(out)]) == 0
    captured = capsys.readouterr()
    assert "hitogata: note: clamped onto the edge of the range of motion: biceps_brachii_l" in captured.err
    assert "→ 150.0°" in captured.out and out.is_file()


def test_list_names_the_muscles_and_dofs(female_args, capsys) -> None:
    assert main(["pose", "--list"]) == 0
    out = capsys.readouterr().out
    assert "muscles (114;" in out and "degrees of freedom (140;" in out
    assert "biceps_brachii_l" in out and "forearm_l.flexion" in out


@pytest.mark.parametrize(
    "args,message",
    [
        (["--muscle", "bicep_l=0.25"], "--muscle 'bicep_l': no muscle of that name; did you mean"),
        (["--muscle", "bicep_l=0.25"], "biceps_brachii_l"),
        (["--angle", "elbow_l.flexon=90deg"], "did you mean forearm_l.flexion"),
        (["--angle", "forearm_l.flexion=90"], "--angle forearm_l.flexion '90': write a number with a unit ('deg'"),
        (["--angle", "forearm_l.flexion=170deg"], "forearm_l.flexion = 170.0° clinical: allowed 0.0…150.0°"),
        (["--muscle", "biceps_brachii_l=lots"], "write a contraction (0.25 or 25%; negative = stretched) or a length"),
        (["--muscle", "biceps_brachii_l=2"], "--muscle biceps_brachii_l '2': a contraction is a fraction of the rest length, allowed between -1 and 1; did you mean 2%?"),
        (["--muscle", "biceps_brachii_l=0.99"], "muscle 'biceps_brachii_l': contraction 0.99 is beyond its reach"),
        (["--muscle", "biceps_brachii_l"], "--muscle 'biceps_brachii_l': write NAME=VALUE"),
        (["--muscle", "biceps_brachii_l=10%", "--angle", "forearm_l.flexion=60deg"], "set both by an angle and by"),
        (["--muscle", "biceps_brachii_l=10%", "--muscle", "biceps_brachii_l=5%"], "given twice"),
        (["--skinning", "dqs"], "cannot go in a GLB (glTF viewers skin linearly); write .obj or .ply"),
        (["--contact"], "--contact: the skin's self-contact is resolved on the elastic body; add --elastic"),
    ],
)
def test_bad_input_one_line_and_no_file(tmp_path: Path, female_args, capsys, args: list[str], message: str) -> None:
    assert main(["pose", *args, "--out", str(tmp_path / "posed.glb")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("hitogata: error:") and "\n" not in err and message in err, err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("out,message", [("posed.stl", "allowed: .glb, .obj, .ply"), (None, "--out: give the output file")])
def test_output_path_checked(tmp_path: Path, female_args, capsys, out, message: str) -> None:
    assert main(["pose", *(["--out", str(tmp_path / out)] if out else [])]) == 2
    assert message in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []
