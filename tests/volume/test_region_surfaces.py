"""The tissue regions' surfaces from the regions' own definitions: every region where the body has it,
closed, not crossing themselves, and smooth (no lattice staircase)."""

import numpy as np
import pytest

from hitogata.geometry.mesh_checks import enclosed_volume, is_closed, self_intersections
from hitogata.volume import anatomy as A
from hitogata.volume.region_surfaces import INSET, body_region_surfaces
from hitogata.volume.regions import PELVIC_FLOOR_DROP
from hitogata.volume.surface import SurfaceIndex
from hitogata.volume.trunk import TrunkLandmarks, segment_distance



# Body parts by the rig bones nearest a vertex
PARTS = {"trunk": A.TRUNK_BONES, "head": ("neck02", "neck03", "head"), "upper arm": ("upperarm",),
         "forearm": ("lowerarm",), "hand": ("wrist", "metacarpal", "finger"), "thigh": ("upperleg",),
         "shank": ("lowerleg",), "foot": ("foot", "toe")}


def part_of(bone: str) -> str:
    return next(part for part, names in PARTS.items() if bone.startswith(names))


@pytest.fixture(scope="module")
def surfaces(male):
    return {s.name: s for s in body_region_surfaces(male)}


@pytest.fixture(scope="module")
def counts(male, surfaces):
    """Vertices of each region's surface in each body part."""
    rows = [male.rig.names.index(n) for n in A.BODY_BONES]
    heads, tails = np.asarray(male.rig.heads)[rows], np.asarray(male.rig.tails)[rows]
    out = {}
    for name, surface in surfaces.items():
        nearest = segment_distance(surface.vertices, heads, tails).argmin(axis=1)
        parts = [part_of(A.BODY_BONES[i]) for i in nearest]
        out[name] = {part: parts.count(part) for part in PARTS}
    return out


def test_every_region_is_drawn_where_the_body_has_it(counts):
    """From the regions' definitions, not the 40 mm lattice (which holds none of a hand, 2-23 % of a forearm)."""
    print(counts)
    for part in PARTS:
        assert counts["skin"][part] >= 50 and counts["bone"][part] >= 50, part
    for part in ("trunk", "head", "upper arm", "forearm", "thigh", "shank", "foot"):
        assert counts["muscle"][part] >= 50, part  # the hand: bone capsules (20 mm at least) under the skin
    assert counts["viscera"]["trunk"] > 1000
    assert all(counts["viscera"][part] == 0 for part in ("head", "forearm", "hand", "shank", "foot"))


def test_the_viscera_lie_in_the_trunk(male, surfaces):
    marks = TrunkLandmarks.from_rig(male.rig)
    y = surfaces["viscera"].vertices[:, 1]
    assert y.min() >= marks.hip_height - PELVIC_FLOOR_DROP and y.max() <= marks.neck_height


def test_surfaces_are_closed_outward_and_do_not_cross_themselves(male, surfaces):
    total = 0.0
    for name, surface in surfaces.items():
        volume = enclosed_volume(surface.vertices, surface.faces)
        assert is_closed(surface.faces) and volume > 0, name
        assert len(self_intersections(surface.vertices, surface.faces)) == 0, name
        total += volume
    # the regions fill the body but for the 2 x INSET between neighbours (about 2.5 m² of interfaces)
    assert total == pytest.approx(male.volume, rel=0.12) and total < male.volume


def test_the_skin_region_follows_the_skin_without_a_staircase(male, surfaces):
    """Its outer sheet lies INSET under the skin: marching cubes on a distance field is exact to a fraction of
    a millimetre where a lattice's faces stood up to half an element (20 mm) off."""
    depth = SurfaceIndex(male.vertices, male.faces).distance(surfaces["skin"].vertices)
    outer = depth[depth < 3 * INSET]
    assert len(outer) > 0.3 * len(depth)
    low, high = np.percentile(outer, [5, 95])
    assert INSET - 0.5e-3 < low and high < INSET + 0.5e-3
