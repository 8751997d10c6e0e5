"""The labelled volume model of the default bodies: regions, muscles, bones, fidelity."""

import numpy as np
import pytest

from hitogata.errors import HitogataError
from hitogata.fem.elements import MATERIAL_SAMPLES
from hitogata.volume import MUSCLES, REGIONS, build_body_model, build_trunk_model
from hitogata.volume.anatomy import capsule_radii, skin_thickness
from hitogata.volume.bones import capsule_gap
from hitogata.volume.quality import dihedral_angles, signed_volumes

MUSCLE_LIST_NAMES = {
    "rectus_abdominis", "external_oblique_l", "external_oblique_r", "erector_spinae_l", "erector_spinae_r",
    "pectoralis_major_l", "pectoralis_major_r", "gluteus_maximus_l", "gluteus_maximus_r",
}


@pytest.fixture(scope="module")
def trunk(female):
    return build_trunk_model(female)


@pytest.fixture(scope="module")
def body(male):
    return build_body_model(male, element_size=30.0)


def test_trunk_mesh_quality_and_fidelity(trunk):
    q = trunk.quality
    assert q.inverted == 0 and signed_volumes(trunk.nodes, trunk.tets).min() > 0
    assert q.min_dihedral >= 10.7
    assert np.isclose(np.degrees(dihedral_angles(trunk.nodes, trunk.tets)).min(), q.min_dihedral)
    # The boundary is watertight; where two bone capsules (or a capsule and the skin) nearly
    # touch, two tets may meet along an edge of a capsule's surface (a non-manifold edge).
    faces = trunk.boundary_faces
    edges, counts = np.unique(np.sort(faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1), axis=0, return_counts=True)
    assert np.all(counts % 2 == 0) and np.isin(edges[counts > 2], trunk.bone_nodes).any(axis=1).all()
    assert (counts > 2).sum() < 1e-3 * len(edges)
    assert abs(q.volume_error) < 0.02
    assert q.surface_distance_mean < 0.05 * trunk.element_size
    assert q.surface_distance_max < trunk.element_size
    assert 20_000 < q.n_tets < 80_000


def test_trunk_lies_between_neck_and_hips(trunk, female):
    rig = female.rig
    hips = rig.heads[[rig.index("upperleg01.L"), rig.index("upperleg01.R")], 1].mean()
    neck = rig.heads[rig.index("neck01"), 1]
    assert trunk.nodes[:, 1].min() >= hips - 1e-9 and trunk.nodes[:, 1].max() <= neck + 1e-9
    # The arms are cut off: nothing reaches the elbows.
    elbow = abs(rig.heads[rig.index("lowerarm01.L"), 0])
    assert np.abs(trunk.nodes[:, 0]).max() < elbow
    # Skin faces and cut faces both exist; the skin faces carry most of the boundary.
    assert 0.5 < trunk.boundary_on_skin.mean() < 1.0


def test_trunk_regions(trunk, female):
    assert trunk.region_names == REGIONS
    volumes = trunk.quality.region_volumes
    assert all(volumes[name] > 0 for name in REGIONS)
    total = trunk.quality.volume
    # Thoracic + abdominal cavity: ~13–17 L of a 30–35 L adult trunk; a plausible band.
    assert 0.2 < volumes["viscera"] / total < 0.6
    assert volumes["bone"] / total < 0.1
    # The skin+fat layer's volume is about its thickness times the skin's area.
    t = skin_thickness(female.bmi, 0.0)
    assert 0.005 < t < 0.03
    faces = trunk.nodes[trunk.boundary_faces[trunk.boundary_on_skin]]
    area = 0.5 * np.linalg.norm(np.cross(faces[:, 1] - faces[:, 0], faces[:, 2] - faces[:, 0]), axis=1).sum()
    assert 0.6 < volumes["skin"] / (area * t) < 1.6
    # Skin tets touch the skin; viscera never do.
    touched = np.unique(trunk.boundary_tets[trunk.boundary_on_skin])
    assert not np.any(trunk.region[touched] == REGIONS.index("viscera"))


def test_regions_sampled_inside_tets_converge_faster_than_centroid_labels(trunk, female):
    """The skin and muscle layers (~20 mm) cross the tets; their volumes from the sample points
    of a 40 mm trunk are within 3 % of the 20 mm trunk's, where centroid labels are off up to 7 %."""
    samples = trunk.region_samples
    assert samples.shape == trunk.muscle_samples.shape == (len(trunk.tets), len(MATERIAL_SAMPLES[1]))
    named = trunk.muscle_samples >= 0  # named muscles are muscle tissue, with unit fibres there only
    assert np.all(samples[named] == REGIONS.index("muscle"))
    assert np.allclose(np.linalg.norm(trunk.fibre_samples[named], axis=1), 1.0)
    assert np.all(trunk.fibre_samples[~named] == 0.0)
    assert np.allclose(trunk.region_fractions.sum(axis=1), 1.0)
    volumes = signed_volumes(trunk.nodes, trunk.tets)
    assert sum(trunk.quality.region_volumes[n] for n in ("viscera", "muscle", "skin")) == pytest.approx(volumes.sum())
    coarse = build_trunk_model(female, element_size=40.0)
    coarse_tets = signed_volumes(coarse.nodes, coarse.tets)
    for name in ("viscera", "muscle", "skin"):
        fine = trunk.quality.region_volumes[name]
        sampled = coarse.quality.region_volumes[name] / fine - 1
        labelled = coarse_tets[coarse.region == REGIONS.index(name)].sum() / fine - 1
        print(f"\n{name}: 40 mm vs 20 mm, sampled {sampled:+.1%}, centroid labels {labelled:+.1%}")
        assert abs(sampled) < 0.03 and abs(sampled) < abs(labelled)


def test_trunk_named_muscles(trunk):
    assert set(trunk.muscle_names) == MUSCLE_LIST_NAMES and trunk.muscle_names == MUSCLES
    named = trunk.muscle >= 0
    assert np.all(trunk.region[named] == REGIONS.index("muscle"))
    assert np.allclose(np.linalg.norm(trunk.fibres[named], axis=1), 1.0)
    assert np.all(trunk.fibres[~named] == 0.0)
    centroids = trunk.nodes[trunk.tets].mean(axis=1)
    for k, name in enumerate(trunk.muscle_names):
        mine = trunk.muscle == k
        assert mine.sum() > 50, name
        x = centroids[mine, 0]
        if name.endswith("_l"):
            assert np.all(x > 0), name
        elif name.endswith("_r"):
            assert np.all(x < 0), name
    up = np.array([0.0, 1.0, 0.0])

    def fibre_cos(name):
        return np.abs(trunk.fibres[trunk.muscle == MUSCLES.index(name)] @ up)

    assert np.median(fibre_cos("rectus_abdominis")) > 0.95  # vertical
    assert np.median(fibre_cos("erector_spinae_l")) > 0.95
    oblique = trunk.fibres[trunk.muscle == MUSCLES.index("external_oblique_l")]
    # Down and forward (a fibre is a line: compare with its sign fixed to point down).
    oblique = oblique * -np.sign(oblique[:, 1:2])
    assert np.median(oblique[:, 2]) > 0.3 and np.median(oblique[:, 1]) < -0.3
    pec = trunk.fibres[trunk.muscle == MUSCLES.index("pectoralis_major_l")]
    assert np.median(np.abs(pec[:, 0])) > 0.7  # towards the arm
    # Front and back muscles lie on the right side of the spine.
    z = {name: np.median(centroids[trunk.muscle == MUSCLES.index(name), 2]) for name in MUSCLES}
    assert z["rectus_abdominis"] > z["erector_spinae_l"] and z["pectoralis_major_r"] > z["gluteus_maximus_r"]


def test_bone_nodes_attached_to_spine_and_pelvis(trunk, female):
    assert len(trunk.bone_nodes) > 0
    attached = {trunk.bone_names[k] for k in np.unique(trunk.bone_node_bone)}
    assert {"spine05", "spine03", "spine01", "pelvis.L", "pelvis.R"} <= attached
    # The soft tissue is meshed round the bone capsules: the held nodes lie on their capsule.
    assert not np.any(trunk.region == REGIONS.index("bone"))
    rig_rows = [female.rig.index(n) for n in trunk.bone_names]
    heads, tails = female.rig.heads[rig_rows], female.rig.tails[rig_rows]
    gap = capsule_gap(trunk.nodes[trunk.bone_nodes], heads, tails, capsule_radii(trunk.bone_names))
    assert np.abs(gap[np.arange(len(gap)), trunk.bone_node_bone]).max() < 1e-6
    assert np.all(gap >= -1e-6)  # and inside none


def test_region_interfaces_are_faces_between_regions(trunk):
    assert ("viscera", "muscle") in trunk.interfaces and ("muscle", "skin") in trunk.interfaces
    for (a, b), faces in trunk.interfaces.items():
        assert REGIONS.index(a) < REGIONS.index(b) and faces.shape[1] == 3 and len(faces) > 0


def test_whole_body_model(body, male):
    q = body.quality
    assert q.inverted == 0 and q.min_dihedral >= 10.7
    assert abs(q.volume_error) < 0.03
    assert q.reference_volume == pytest.approx(male.volume)
    attached = {body.bone_names[k] for k in np.unique(body.bone_node_bone)}
    assert {"head", "upperleg02.L", "lowerleg01.R", "upperarm02.L"} <= attached
    assert all(v > 0 for v in q.region_volumes.values())
    assert (body.muscle == MUSCLES.index("gluteus_maximus_l")).sum() > 50


def test_model_is_deterministic(female):
    a, b = build_trunk_model(female, 40.0), build_trunk_model(female, 40.0)
    for name in ("nodes", "tets", "region", "muscle", "fibres", "bone_nodes", "boundary_faces"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


def test_element_size_sets_resolution_and_is_checked(female):
    coarse = build_trunk_model(female, 40.0)
    assert coarse.element_size == pytest.approx(0.04)
    assert coarse.quality.n_tets < 10_000
    with pytest.raises(HitogataError, match="element_size 1 mm"):
        build_trunk_model(female, 1)
    with pytest.raises(HitogataError, match="extent"):
        from hitogata.volume import build_volume_model

        build_volume_model(female.vertices, female.faces, female.rig, female.skin_weights,
                           bmi=22.0, sex=0.0, extent="arm")
