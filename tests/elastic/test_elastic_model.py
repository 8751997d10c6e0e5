"""The elastic trunk: mesh sanity, constrained and mass-normalised modes, loads, the skin map."""

import numpy as np
import pytest

from hitogata.dynamics.model_cache import cached_dynamics
from hitogata.elastic import build_elastic_model
from hitogata.elastic.model import assemble_system
from hitogata.errors import HitogataError
from hitogata.fem import check_mesh, solve_modes, tet_geometry
from hitogata.fem.verify import solve_static
from hitogata.volume import build_volume_model

SIZE = 50.0  # mm: coarse, so the file runs in seconds; the default model is checked in benchmarks/
N_MODES = 12


@pytest.fixture(scope="module")
def model(female):
    return build_elastic_model(female, element_size=SIZE, n_modes=N_MODES)


def test_no_inverted_elements(model, female):
    check_mesh(model.points, model.elements)  # raises on an inverted or flat tet
    assert model.volume.quality.inverted == 0
    assert model.elements.shape[1] == 10 and model.element == "P2"
    whole = build_volume_model(female.vertices, female.faces, female.rig, female.skin_weights, bmi=female.bmi,
                               sex=female.params.sex, extent="body", element_size=60.0)
    assert whole.quality.inverted == 0
    assert tet_geometry(whole.nodes, whole.tets)[1].min() > 0


def test_region_volumes_are_sane(model):
    volumes = model.region_volumes
    assert set(volumes) == set(model.region_names) == {"bone", "viscera", "muscle", "skin"}
    # The bone capsules are held, not meshed: "bone" is their volume within the trunk.
    assert not np.any(model.region == model.region_names.index("bone"))
    total = tet_geometry(model.points, model.elements)[1].sum() + model.volume.quality.held_volume
    assert sum(volumes.values()) == pytest.approx(total, rel=1e-9)
    assert 20e-3 < total < 45e-3  # an adult trunk, neck to hips, without the arms: 20-45 L
    assert 0.02 < volumes["bone"] / total < 0.10
    assert 0.15 < volumes["viscera"] / total < 0.45
    assert 0.2 < volumes["muscle"] / total < 0.55
    assert 0.1 < volumes["skin"] / total < 0.45
    assert 20.0 < model.mass < 45.0  # kg, the soft tissue


def test_fixed_nodes_follow_bones_and_modes_vanish_there(model):
    fixed = model.fixed_nodes
    assert len(fixed) > 50 and len(fixed) == len(model.fixed_bone)
    assert set(model.volume.bone_nodes.tolist()) <= set(fixed.tolist())
    assert np.all((model.fixed_bone >= 0) & (model.fixed_bone < len(model.volume.bone_names)))
    spine = [model.volume.bone_names.index(n) for n in ("spine01", "spine03", "spine05")]
    assert set(spine) <= set(model.fixed_bone.tolist())
    shapes = model.modes.vectors.reshape(len(model.points), 3, -1)
    assert np.all(shapes[fixed] == 0.0)
    assert np.abs(shapes).max() > 0


def test_frequencies_positive_sorted_and_plausible(model):
    f = model.frequencies
    assert len(f) == N_MODES
    assert np.all(f > 0) and np.all(np.diff(f) >= 0)
    assert 0.5 < f[0] < 20.0  # soft tissue on a fixed skeleton: a few Hz


def test_tissue_is_sampled_in_elements_and_mean_dilatation_unlocks(model, female):
    # Materials come from the regions at each element's sample points: the mass is theirs.
    assert model.dilatation == "mean"
    assert model.M.sum() / 3 == pytest.approx(model.mass, rel=1e-9)
    fractions = model.volume.region_fractions
    assert np.allclose(fractions.sum(axis=1), 1.0)
    mixed = (fractions.max(axis=1) < 1.0 - 1e-9).mean()
    assert 0.3 < mixed < 0.7  # at 50 mm, half the tets straddle the ~20 mm skin and muscle layers
    soft = [model.materials.regions[n].E for n in ("viscera", "muscle", "skin")]
    assert min(soft) - 1e-9 <= model.E.min() and model.E.max() <= max(soft) + 1e-9
    # P2 with the volumetric term in full locks a little at the tissue's nu 0.49: every mode stiffer.
    full = assemble_system(model.volume, female.rig, dilatation="full")
    f_full = solve_modes(full.K, full.M, N_MODES, full.fixed_nodes, tol=1e-6).frequencies
    rise = f_full / model.frequencies - 1
    print(f"\nfull vs mean dilatation at {SIZE:g} mm: +{rise.min():.1%} .. +{rise.max():.1%}")
    assert np.all(rise > 0.01) and np.all(rise < 0.15)


def test_modes_are_mass_normalised(model):
    phi = model.modes.vectors
    assert np.allclose(phi.T @ (model.M @ phi), np.eye(N_MODES), atol=1e-9)
    assert np.allclose(phi.T @ (model.K @ phi), np.diag(model.modes.eigenvalues), rtol=1e-6,
                       atol=1e-6 * model.modes.eigenvalues.max())


def test_muscle_load_moves_that_muscle_most(model):
    name = "rectus_abdominis"
    f = model.muscle_load(name, 0.05)
    u = solve_static(model.K, f, model.fixed_nodes).reshape(-1, 3)
    mine = np.unique(model.elements[model.muscle_elements(name)])
    others = np.setdiff1d(np.arange(len(model.points)), mine)
    size = np.linalg.norm(u, axis=1)
    assert size[mine].mean() > 2.5 * size[others].mean()  # 2.9x at 50 mm
    # contraction shortens the band along its (vertical) fibres: its top comes down, its bottom up
    band = model.points[mine]
    top, bottom = band[:, 1] > np.quantile(band[:, 1], 0.8), band[:, 1] < np.quantile(band[:, 1], 0.2)
    assert u[mine][top, 1].mean() < 0 < u[mine][bottom, 1].mean()
    assert np.allclose(model.muscle_load(name, -0.05), -f)


def test_gravity_load_is_the_weight(model):
    f = model.gravity_load().reshape(-1, 3)
    assert f[:, 1].sum() == pytest.approx(-9.81 * model.mass, rel=1e-9)
    assert np.abs(f[:, [0, 2]].sum(axis=0)).max() < 1e-9 * model.mass


def test_skin_map_reproduces_a_rigid_translation(model, female):
    W = model.skin_vertex_map
    assert W.shape == (len(female.vertices), len(model.points))
    rows = np.asarray(W.sum(axis=1)).ravel()
    assert rows.min() >= -1e-12 and rows.max() <= 1 + 1e-12
    inside = np.abs(rows - 1.0) < 1e-12
    torso = (np.abs(female.vertices[:, 0]) < 0.08) & (np.abs(female.vertices[:, 1] - 1.2) < 0.1)  # chest, belly, back
    assert np.all(inside[torso])
    assert 1000 < inside.sum() < len(rows)  # the trunk's skin, not the head or the feet
    shift = np.array([0.01, -0.02, 0.03])
    moved = model.skin_displacement(np.tile(shift, len(model.points)))
    assert np.abs(moved[inside] - shift).max() < 1e-12
    assert np.abs(model.skin_displacement(np.zeros(3 * len(model.points)))).max() == 0.0
    feet = female.vertices[:, 1] < 0.2
    assert np.all(rows[feet] == 0.0)


def test_damping(model):
    zeta = model.damping_ratios
    assert np.all(zeta > 0.1) and np.all(zeta < 0.5)
    assert model.alpha > 0 and model.beta > 0


def test_options_p1_elastic_bone_and_errors(female, model):
    p1 = build_elastic_model(female, element_size=60.0, element="P1", n_modes=4, bone="elastic",
                             alpha_beta=(1.0, 0.01), volume=None)
    assert p1.elements.shape[1] == 4 and p1.alpha == 1.0 and p1.beta == 0.01
    assert len(p1.fixed_nodes) < len(p1.volume.bone_nodes)  # only the bones' axes follow the skeleton
    assert np.all(p1.frequencies > 0)
    rigid = build_elastic_model(female, element="P1", n_modes=4, volume=p1.volume)
    assert np.allclose(p1.frequencies, rigid.frequencies, rtol=0.1)  # GPa bone barely moves
    assert len(rigid.fixed_nodes) == len(rigid.volume.bone_nodes)  # cuts free: exactly the bone nodes
    held = build_elastic_model(female, element="P1", n_modes=4, volume=p1.volume, cuts="attached")
    cut = np.unique(held.volume.boundary_faces[~held.volume.boundary_on_skin])
    assert set(cut.tolist()) <= set(held.fixed_nodes.tolist())  # the neck, hip and arm cuts are held
    assert np.all(held.frequencies > rigid.frequencies)  # held cut faces: a stiffer trunk
    for kwargs, words in [({"element": "P3"}, "element 'P3'"), ({"bone": "soft"}, "bone 'soft'"),
                          ({"cuts": "sewn"}, "cuts 'sewn'"), ({"dilatation": "half"}, "dilatation 'half'"),
                          ({"damping_ratios": ((1, 0.1), (10, 0.1)), "alpha_beta": (1, 0)}, "not both"),
                          ({"alpha_beta": (-1.0, 0.0)}, "alpha"), ({"extent": "legs"}, "extent")]:
        with pytest.raises(HitogataError, match=words):
            build_elastic_model(female, **{"volume": model.volume, **kwargs} if "extent" not in kwargs else kwargs)
    with pytest.raises(HitogataError, match="rectus_abdominis"):
        model.muscle_load("biceps_l", 0.1)


def test_whole_body_has_no_floating_or_hinged_pieces(female):
    # at 60 mm the lattice leaves a fingertip island and tets hanging on by an edge: they follow a bone
    body = build_elastic_model(female, extent="body", element_size=60.0, n_modes=6)
    assert body.frequencies[0] > 1.0
    bone = body.volume.quality.held_volume * body.materials.regions["bone"].rho
    assert 50.0 < body.mass + bone < 75.0  # the whole 62 kg body, at the tissue densities
    rows = np.asarray(body.skin_vertex_map.sum(axis=1)).ravel()
    torso = (np.abs(female.vertices[:, 0]) < 0.1) & (np.abs(female.vertices[:, 1] - 1.2) < 0.1)
    thighs = (np.abs(np.abs(female.vertices[:, 0]) - 0.1) < 0.03) & (np.abs(female.vertices[:, 1] - 0.7) < 0.05)
    assert rows.max() < 1 + 1e-12 and np.all(rows[torso | thighs] > 1 - 1e-12)  # the tissue's skin, whole


def test_whole_body_holds_hands_and_toes(male):
    """The skeleton moves fingers and toes, so the whole body holds them: its lowest modes are soft
    tissue on the trunk and legs, not fingers and toes flapping on the wrist and foot capsules
    (without their capsules, at 40 mm: a hand at 1.18 Hz, the toes at 1.37 Hz)."""
    body = cached_dynamics(male, extent="body", element_size=40.0, n_modes=6).model  # as the frequencies' golden test
    names = body.volume.bone_names
    assert {"finger3-2.L", "metacarpal2.R", "toe1-1.L"} <= set(names)
    held = {names[b] for b in body.fixed_bone}  # the tissue round them, nearest to them (most lies inside)
    assert any(n.startswith(("finger", "metacarpal")) for n in held) and any(n.startswith("toe") for n in held)
    element_mass = body.rho * tet_geometry(body.points, body.elements)[1]
    mass = np.bincount(body.elements.ravel(), weights=np.repeat(element_mass, 10) / 10, minlength=len(body.points))
    shapes = body.modes.vectors.reshape(len(body.points), 3, -1)
    rig = male.rig
    fingertips = [rig.tails[rig.index(n)] for n in names if n.startswith("finger")]
    hips, neck = rig.heads[rig.index("upperleg01.L"), 1], rig.heads[rig.index("neck01"), 1]
    for k in range(6):
        energy = mass * (shapes[:, :, k] ** 2).sum(axis=1)
        centre = energy @ body.points / energy.sum()
        nearest = min(np.linalg.norm(centre - np.asarray(tip)) for tip in fingertips)
        print(f"mode {k + 1}: {body.frequencies[k]:.2f} Hz, centred at {np.round(centre * 100)} cm, "
              f"{nearest * 100:.0f} cm from a fingertip")
        assert nearest > 0.15  # no hand mode
        if k == 0:  # the lowest is the abdomen's
            assert abs(centre[0]) < 0.05 and hips < centre[1] < neck
    assert body.frequencies[0] > 1.8
