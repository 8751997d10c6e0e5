"""A heavy body's rest skin where it meets itself: touching, never passing through.

MakeHuman's weight targets extrapolated past their slider (`hitogata.body.shape.WEIGHT_MAX`) move each
vertex along a straight line fixed by the target, heedless of the skin it meets: at BMI 50 the inner
thighs pass into each other, the upper arm into the flank, the belly and the breasts fold through
the skin below them (151–228 crossing triangle pairs, against 0–35 for MakeHuman's own bodies: the
base mesh's eyes, toes and fingers). A pattern maker's heavy body has its thighs touching, not
crossing.

The rest skin is therefore reached along a path of weights from MakeHuman's heaviest body (weight 1,
free of crossings beyond the base mesh's own) to the asked weight, as the elastic body reaches a
posture (`hitogata.geometry.barrier_contact`): at each step the skin near contact ends within the
barrier's reach (2 mm) of the skin it meets, its enclosed volume held to the extrapolated body's, so
the tissue a contact presses aside swells the free skin round it and the mass is kept. The skin
that may meet is the skin within reach of another contact group along the path, and the skin of
every pair that crosses in the extrapolated body, grown by a few rings.

Skin meeting its own neighbourhood (a pleat under the belly or a breast, a finger into the next:
nearer at rest than the barrier lets meet) is held back towards the path's start where it would
still cross (`hitogata.geometry.offset_limit`, crossings only), which takes a little volume; the
body's builder asks for that much more mass (`hitogata.body.Body.from_measurements`). Folds are
left: the lower belly of a heavy body folds under onto the pubis, a crease as on a living body,
and holding the folds back as well pulled it back 8 cm towards MakeHuman's heaviest belly (3 cm
for the crossings alone).

Contact groups come from the rig (this layer has no skeleton): a vertex belongs to the limb of the
bone holding most of its skinning weight, found up the rig's chain (thigh, shank, foot, upper arm,
forearm, hand, shoulder, neck, head, each side apart); the root, pelvis, spine and breast bones are
the trunk's, which may fold onto itself, as may every limb but the hands, feet and head, whose small
triangles lie close everywhere.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp

from hitogata.body.rig import Rig
from hitogata.geometry.barrier_contact import BARRIER_DEFAULTS, _grow, barrier_resolve, contact_regions
from hitogata.geometry.contact import SelfContact
from hitogata.geometry.mesh_checks import self_intersections
from hitogata.geometry.offset_limit import OffsetLimiter

# rig bones (side suffix dropped) whose skin and their descendants' make one contact group
LIMB_ROOTS = ("upperleg01", "lowerleg01", "foot", "upperarm01", "lowerarm01", "wrist", "clavicle", "neck01", "head")
RIGID = ("foot", "wrist", "head")  # groups whose skin does not fold onto itself
WEIGHT_STEP = 0.15  # the longest step of weight along the path: the barrier's CCD follows the skin
CROSSING_RINGS = BARRIER_DEFAULTS.rings + 1  # rings round a crossing of the extrapolated body that are free to move


def contact_groups(rig: Rig, skin_weights: sp.spmatrix) -> tuple[np.ndarray, tuple[int, ...]]:
    """(V,) each skin vertex's contact group, and the groups that may fold onto themselves (module note).
    `skin_weights` (V, B) over the rig's bones."""
    root_of = np.zeros(len(rig.names), dtype=np.intp)  # 0: the trunk; k + 1: the limb of bone k
    for bone in range(len(rig.names)):
        k = bone
        while k >= 0 and rig.names[k].split(".")[0] not in LIMB_ROOTS:
            k = int(rig.parents[k])
        root_of[bone] = 0 if k < 0 else k + 1
    dominant = np.asarray(sp.csr_matrix(skin_weights).argmax(axis=1)).ravel()
    roots, groups = np.unique(root_of[dominant], return_inverse=True)
    folding = tuple(g for g, r in enumerate(roots) if r == 0 or rig.names[r - 1].split(".")[0] not in RIGID)
    return groups.astype(np.intp), folding


def touching_skin(path: Sequence[np.ndarray], faces: np.ndarray, groups: np.ndarray, folding: Sequence[int]
                  ) -> np.ndarray:
    """The skin (V, 3) at the last of `path`'s skins (each (V, 3): the body at increasing weights, the
    first free of crossings beyond the base mesh's own) with no skin passing through other skin that
    the first did not cross (module note)."""
    start, target = np.asarray(path[0], dtype=float), np.asarray(path[-1], dtype=float)
    test = SelfContact(start, faces, groups)
    crossing_at_start, crossing = _crossing_vertices(start, faces), _crossing_vertices(target, faces)
    free = contact_regions(path[1:], test) | _grow(crossing & ~crossing_at_start, test, CROSSING_RINGS)[None]
    free &= ~_grow(crossing_at_start, test, BARRIER_DEFAULTS.rings)[None]  # the base mesh's own crossings: no barrier starts there
    skin = barrier_resolve(path, test, folding=folding, free=free).vertices if free.any() else target
    limited, _ = OffsetLimiter(start, faces).hold_crossings(start, skin - start)
    return np.asarray(limited)


def _crossing_vertices(x: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(V,) bool: the corners of every crossing face pair of the skin x."""
    out = np.zeros(len(x), dtype=bool)
    out[np.unique(faces[self_intersections(x, faces).ravel()])] = True
    return out
