"""The one owner of each skin vertex's part, and every split of the body as named sets of parts."""

from __future__ import annotations

import numpy as np
import pytest

from hitogata.body.model import Body
from hitogata.body.rest_contact import RIGID, contact_groups
from hitogata.garment.stretch import garment_zones
from hitogata.made_to_measure.scan_fit.regions import REGIONS, vertex_regions
from hitogata.measure.measurements import tape_skin
from hitogata.measure.zones import body_zones
from hitogata.posing.body_split import SPLITS, dominant_bone_parts, part_groups, vertex_parts
from hitogata.posing.pose import poser_for
from hitogata.skin.contact import GROUPS, vertex_groups

PARTITIONS = [name for name, split in SPLITS.items() if split.rule != "within"]


@pytest.fixture(scope="module", params=["female", "male"])
def body(request: pytest.FixtureRequest) -> Body:
    return request.getfixturevalue(request.param)


def test_the_owner_gives_every_skin_vertex_one_of_the_skeletons_parts(body: Body) -> None:
    poser = poser_for(body)
    owner = vertex_parts(body)
    assert owner.shape == (len(body.vertices),)
    assert owner.min() >= 0 and owner.max() < len(poser.skeleton.names) == 65
    assert vertex_parts(body) is owner  # found once, kept with the body
    weights = poser.skin.weights.toarray()
    assert np.array_equal(weights[np.arange(len(owner)), owner], weights.max(axis=1))
    # every part but the atlas (cervical_1) owns skin on the default bodies: 64 of the 65
    assert len(np.unique(owner)) >= 62


@pytest.mark.parametrize("split", PARTITIONS)
def test_a_split_by_parts_gives_each_shipped_part_one_group(female: Body, split: str) -> None:
    names = poser_for(female).skeleton.names
    named = [part for parts in SPLITS[split].groups.values() for part in parts]
    assert sorted(named) == sorted(names)


def test_contact_groups_hold_most_of_each_vertexs_weight_on_the_tables_parts(body: Body) -> None:
    poser = poser_for(body)
    names = poser.skeleton.names
    weights = poser.skin.weights.toarray()
    sums = np.column_stack([weights[:, [names.index(p) for p in parts]].sum(axis=1) for parts in GROUPS.values()])
    groups = vertex_groups(poser.skin.weights, names)
    assert np.allclose(sums[np.arange(len(groups)), groups], sums.max(axis=1), rtol=0, atol=1e-12)
    # the owning part's group is the vertex's contact group but at the seams: 63-73 of 12213 vertices apart
    by_owner = part_groups("contact groups", names)[vertex_parts(body)]
    assert 0 < np.count_nonzero(by_owner != groups) < 0.01 * len(groups)


def same_partition(a: np.ndarray, b: np.ndarray) -> bool:
    pairs = np.unique(np.column_stack([a, b]), axis=0)
    return len(pairs) == len(np.unique(a)) == len(np.unique(b))


def test_rest_contact_groups_are_the_tables_over_the_dominant_bones_part(body: Body) -> None:
    poser = poser_for(body)
    groups, folding = contact_groups(body.rig, body.skin_weights)
    table = part_groups("rest contact groups", poser.skeleton.names)[dominant_bone_parts(poser)]
    assert same_partition(groups, table)
    names = list(SPLITS["rest contact groups"].groups)
    folds = {names[int(table[np.flatnonzero(groups == g)[0]])] for g in folding}
    assert folds == {n for n in names if not n.startswith(tuple(r.replace("wrist", "hand") for r in RIGID))}


def test_fit_regions_follow_the_rig_bones_names(body: Body) -> None:
    """Each region's rig bones are the ones its name says (MakeHuman's .L the body's left)."""
    prefixes = {"arm": ("upperarm", "lowerarm"), "hand": ("wrist", "metacarpal", "finger"),
                "leg": ("upperleg", "lowerleg"), "foot": ("foot", "toe"),
                "trunk": ("spine", "breast", "pelvis", "clavicle", "shoulder", "root")}
    poser = poser_for(body)
    dominant = np.asarray(body.skin_weights.argmax(axis=1)).ravel()
    regions = vertex_regions(body)
    for k, region in enumerate(REGIONS):
        bones = {body.rig.names[b] for b in np.unique(dominant[regions == k])}
        kind = region.split()[-1]
        if kind in prefixes:
            assert all(b.startswith(prefixes[kind]) for b in bones), region
        else:
            assert not any(b.startswith(sum(prefixes.values(), ())) for b in bones), region
        if region.startswith(("left", "right")):
            assert all(b.endswith(".L" if region.startswith("left") else ".R") for b in bones), region
    assert np.array_equal(regions, part_groups("fit regions", poser.skeleton.names)[dominant_bone_parts(poser)])


def lies_within(split: str, chosen: dict[str, np.ndarray], body: Body) -> None:
    names = poser_for(body).skeleton.names
    owner = vertex_parts(body)
    for group, vertices in chosen.items():
        parts = {names[p] for p in owner[vertices]}
        assert vertices.size and parts <= set(SPLITS[split].groups[group]), (split, group, parts)


def test_zones_and_tape_skin_lie_on_the_tables_parts(body: Body) -> None:
    faces = body.faces
    lies_within("strain zones", {z: np.unique(faces[f]) for z, f in body_zones(body).items()}, body)
    lies_within("garment zones", {z: np.unique(faces[f]) for z, f in garment_zones(body)[0].items()}, body)
    lies_within("tape skin", {t: np.flatnonzero(m) for t, m in tape_skin(body).items()}, body)
