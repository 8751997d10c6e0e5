"""A pose you can measure: the elastic skin of one pose from one call, written by `hitogata pose
--elastic`, read back by `hitogata measure` (OBJ/PLY with the pose beside it as JSON)."""

import json

import numpy as np
import pytest
import trimesh

from hitogata import disk_cache
from hitogata.cli import main
from hitogata.dynamics.model_cache import cached_dynamics
from hitogata.elastic import load_materials
from hitogata.elastic.stored import DeferredMatrix
from hitogata.skin.single_pose import ELEMENT_SIZE, elastic_dynamics, elastic_pose
from hitogata.measure.body_lines import body_lines
from hitogata.skin.fine_skin import body_fine_skinning


@pytest.fixture()
def female_args(female, monkeypatch):
    monkeypatch.setattr("hitogata.commands.body_file.body_from_args", lambda args: female)
    return female


def test_elastic_pose_returns_the_elastic_skin(female):
    held = elastic_pose(elastic_dynamics(female), clinical={"forearm_l.flexion": np.radians(120)})
    assert held.vertices.shape == female.vertices.shape and np.isfinite(held.vertices).all()
    assert held.quality.inverted == 0
    moved = np.linalg.norm(held.vertices - held.skinned, axis=1)
    assert 0.001 < moved.max() < 0.05  # the quasi-static correction: mm to cm at the bent elbow
    fine = held.fine_vertices()
    fs = body_fine_skinning(female).fine
    assert fine.shape == fs.vertices.shape
    skinned_fine = body_fine_skinning(female).surface(held.posed.pose, "dqs")
    carried = fs.carry(held.vertices - held.skinned)
    assert np.abs(fine - skinned_fine - carried).max() < 1e-9  # the fine skin carries the elastic field
    lines = body_lines(female, fs.vertices, fs.faces)
    line = lines["elbow_posterior"]
    assert line.length(fine) > line.length(fs.vertices)  # the skin over the olecranon stretches


def test_pose_elastic_writes_a_measurable_file(tmp_path, female_args, capsys):
    out = tmp_path / "bent.glb"
    assert main(["pose", "--elastic", "--angle", "elbow_l.flexion=120deg", "--angle", "shoulder_r.flexion=150deg",
                 "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    mesh, side = tmp_path / "bent_elastic.ply", tmp_path / "bent_elastic.json"
    assert out.is_file() and mesh.is_file() and side.is_file()
    assert "elastic body: elastic  inverted    0" in printed
    extras = json.loads(side.read_text())
    assert extras["surface"] == "elastic" and extras["skinning"] == "dqs"
    assert extras["clinical_angles_deg"]["forearm_l.flexion"] == pytest.approx(120.0)
    report = tmp_path / "report"
    assert main(["measure", str(mesh), "--out", str(report)]) == 0
    zones = json.loads((report / "measurements.json").read_text())["zone_strain_percent"]
    assert zones["elbow_left"]["stretch_mean"] > 5.0 and abs(zones["knee_left"]["stretch_mean"]) < 0.5
    assert (report / "strain.png").is_file()


def test_measure_reads_a_dqs_obj_with_its_json(tmp_path, female_args, capsys):
    out = tmp_path / "twist.obj"
    assert main(["pose", "--skinning", "dqs", "--angle", "knee_l.flexion=90deg", "--out", str(out)]) == 0
    assert (tmp_path / "twist.json").is_file()
    assert main(["measure", str(out), "--out", str(tmp_path / "r")]) == 0
    zones = json.loads((tmp_path / "r" / "measurements.json").read_text())["zone_strain_percent"]
    assert zones["knee_left"]["stretch_mean"] > 5.0 and abs(zones["elbow_left"]["stretch_mean"]) < 0.5
    (tmp_path / "twist.json").unlink()
    capsys.readouterr()
    assert main(["measure", str(out), "--out", str(tmp_path / "r2")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.endswith(f"{out}: no twist.json beside it; allowed a .glb written by `hitogata body` or "
                        "`hitogata pose`, or an .obj/.ply written by `hitogata pose` with its .json")
    assert not (tmp_path / "r2" / "measurements.json").exists()


@pytest.mark.slow
def test_pose_elastic_contact_writes_the_contact_resolved_skin(tmp_path, female_args, capsys):
    out = tmp_path / "knee.ply"
    assert main(["pose", "--elastic", "--contact", "--skinning", "dqs", "--angle", "knee_l.flexion=135deg",
                 "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    extras = json.loads((tmp_path / "knee.json").read_text())
    assert extras["surface"] == "elastic" and extras["contact"] is True and extras["slide"] is True
    held = elastic_pose(elastic_dynamics(female_args), clinical={"shank_l.flexion": np.radians(135)}, contact=True,
                        slide=True)
    written = trimesh.load(out, process=False)
    assert np.abs(written.vertices - held.vertices).max() < 1e-6  # the library's contact-resolved, slid skin
    assert "skin inside another part: 0 vertices, deepest 0.0 mm\n" in printed
    coarse = held.slide.coarse
    assert f"skin slid over the fascia where stretched beyond +95 %: {int(coarse.free.sum())} vertices free" \
        in printed
    fine = tmp_path / "knee_fine.ply"  # the fine skin slid on its own: its own file, named in the .json
    assert extras["fine_skin"] == "knee_fine.ply"
    assert np.abs(trimesh.load(fine, process=False).vertices - held.fine_vertices()).max() < 1e-6
    # `measure` strains that file: the same fine skin grown by 10 % stretches every zone by 1.1
    def elbow_stretch(report: str) -> float:
        assert main(["measure", str(out), "--out", str(tmp_path / report)]) == 0
        return json.loads((tmp_path / report / "measurements.json").read_text())["zone_strain_percent"][
            "elbow_left"]["stretch_mean"]

    as_written = elbow_stretch("r0")
    scaled = trimesh.load(fine, process=False)
    scaled.vertices = scaled.vertices * 1.1
    scaled.export(fine)
    assert elbow_stretch("r") == pytest.approx(1.1 * (100 + as_written) - 100, abs=1e-3)  # the PLY: float32
    fine.unlink()
    capsys.readouterr()
    assert main(["measure", str(out), "--out", str(tmp_path / "r2")]) == 2
    assert capsys.readouterr().err.strip().endswith(
        f"{tmp_path / 'knee.json'}: fine_skin = 'knee_fine.ply': no such file; allowed the name of the fine "
        "skin's .ply beside knee.json, written with it by `hitogata pose`")


def test_a_held_posture_from_the_model_cache_reads_neither_k_nor_m(female, monkeypatch):
    """The next process's model, read from the disk cache, poses the same skin bit for bit without reading
    the stiffness and mass matrices (four fifths of the entry)."""
    monkeypatch.delenv(disk_cache.NO_CACHE_ENV, raising=False)
    options = {"extent": "body", "element_size": ELEMENT_SIZE, "n_modes": 0, "materials": load_materials()}
    cached_dynamics(female, **options)  # stored here if no test before stored it (elastic_dynamics' entry)
    stored = cached_dynamics(female, **options)
    clinical = {"forearm_l.flexion": np.radians(120)}
    held = elastic_pose(stored, clinical=clinical)
    np.testing.assert_array_equal(held.vertices, elastic_pose(elastic_dynamics(female), clinical=clinical).vertices)
    assert isinstance(stored.model.K, DeferredMatrix) and isinstance(stored.model.M, DeferredMatrix)
    assert not stored.model.K.arrays_read and not stored.model.M.arrays_read


@pytest.mark.slow
def test_a_held_posture_does_not_hang_on_round_off(male):
    """A nudge of the skinned nodes by round-off (1e-14 relative) leaves the skin's elastic offset where it was:
    the held posture's steps converge, and their Chebyshev weights are fixed (Anderson-mixed steps moved this
    skin by centimetres, docs/decisions/0061-a-held-posture-that-converges.md)."""
    from hitogata.dynamics.quality import STATIC_ITERATIONS
    from hitogata.dynamics.quasistatic import HELD
    from hitogata.skeleton.extreme_poses import extreme_poses

    dynamics = elastic_dynamics(male)
    rng = np.random.default_rng(0)
    for name in ("seated 90/90", "trunk flexion 80°"):
        posed = dynamics.poser.pose(clinical=extreme_poses(dynamics.poser.skeleton)[name], skinning="dqs")
        g, r = dynamics.rig.pose(posed.pose.rotations, posed.pose.translations)
        offsets = []
        for skinned in (g[0], g[0] * (1.0 + 1e-14 * rng.standard_normal(g[0].shape))):
            delta, _ = dynamics.quasi_static(skinned, r[0], None, None, STATIC_ITERATIONS, acceleration=HELD)
            offsets.append(dynamics.rig.skin_map @ delta)
        assert np.linalg.norm(offsets[1] - offsets[0], axis=1).max() < 1e-4, name  # m


@pytest.mark.slow
def test_a_held_posture_ends_at_the_plain_steps_equilibrium(male):
    """The male's trunk flexion folds the belly: plain local/global steps take 672 to converge, and stopped
    at 200 they left the skin 31 mm from where they end. The accelerated steps converge within the step cap
    and land where the plain steps do, within what a step tolerance of 0.01 mm leaves (docs/decisions/
    0062-a-held-posture-by-chebyshev-steps.md); more extrapolation (ρ = 0.99) lands 30 mm away."""
    from hitogata.dynamics.quality import STATIC_ITERATIONS
    from hitogata.dynamics.quasistatic import HELD
    from hitogata.skeleton.extreme_poses import extreme_poses

    dynamics = elastic_dynamics(male)
    posed = dynamics.poser.pose(clinical=extreme_poses(dynamics.poser.skeleton)["trunk flexion 80°"],
                                skinning="dqs")
    g, r = dynamics.rig.pose(posed.pose.rotations, posed.pose.translations)
    fast, size = dynamics.quasi_static(g[0], r[0], None, None, STATIC_ITERATIONS, acceleration=HELD)
    plain, plain_size = dynamics.quasi_static(g[0], r[0], None, None, 2000, acceleration=None)
    assert size <= 1e-5 and plain_size <= 1e-5  # m: both converged
    assert np.linalg.norm(dynamics.rig.skin_map @ (fast - plain), axis=1).max() < 1e-3  # m


def test_every_piece_of_the_tissue_is_held_by_a_bone(male):
    """No piece of the quasi-statics' mesh hangs on released joint nodes alone: there its matrix is singular
    and round-off alone placed the piece (a tet of the default male's was thrown a metre in a step)."""
    from scipy.sparse.csgraph import connected_components
    import scipy.sparse as sp

    statics = elastic_dynamics(male).statics
    corners = statics.elements[:, :4]
    n = len(statics.points)
    pairs = np.stack([np.repeat(corners[:, :1], 4, axis=1).ravel(), corners.ravel()])
    pieces, piece = connected_components(sp.csr_matrix((np.ones(pairs.shape[1]), tuple(pairs)), shape=(n, n)),
                                         directed=False)
    assert pieces > 1  # pieces the mesh keeps apart from the body's main one
    assert set(piece[statics.fixed]) == set(range(pieces))
