"""Which part of the body owns each skin vertex, and every way the library splits the body, in parts.

The owner (`vertex_parts`): each skin vertex belongs to the skeleton part (of the skeleton list's
parts) holding most of its skinning weight, the part whose motion carries it most when posed; found
once per body and kept with it (`Body.prepared`).

`SPLITS` names, for each way the library divides the body, its groups as sets of parts, and the rule
that puts a skin vertex in a group:

- `owner` splits: a vertex is in the group of its owning part;
- the contact groups (`hitogata.skin.contact`): in the group holding most of the vertex's part weight
  (summed over the group's parts: a vertex weighted 0.3/0.3 to two chest vertebrae and 0.4 to the
  upper arm is the chest's);
- the fit regions (`hitogata.made_to_measure.scan_fit.regions`) and the heavy body's rest-contact
  groups (`hitogata.body.rest_contact`, below the skeleton's layer, in the rig's own bones): in the
  group of the part carrying the vertex's dominant rig bone (`bone_carriers`);
- the muscle folders (`hitogata.viewer.groups`) split the parts, not the skin: a muscle goes to
  the folder of the part whose joint it moves first;
- the strain zones (`hitogata.measure.zones`), the garment zones (`hitogata.garment.stretch`) and
  the skin a tape may rest on (`hitogata.measure.measurements.TAPE_SKIN`) are chosen by a weight
  rule (`mainly_weighted`) with a radius round a joint, a facing test on the rest normals or the
  landmarks' levels; their parts are the ones the skin they choose lies on (checked on the default
  bodies).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
import scipy.sparse as sp

from hitogata.body.model import Body
from hitogata.posing.pose import Poser, poser_for
from hitogata.skeleton.weights import bone_parts

MAIN_WEIGHT = 0.5  # a vertex follows a set of rig bones when its summed skinning weight on them is at least this


def _range(stem: str, first: int, last: int) -> tuple[str, ...]:
    return tuple(f"{stem}_{k}" for k in range(first, last + 1))


def _sided(side: str, *parts: str) -> tuple[str, ...]:
    return tuple(f"{part}_{side}" for part in parts)


CERVICAL = _range("cervical", 1, 7)
THORACIC = _range("thoracic", 1, 12)
LUMBAR = _range("lumbar", 1, 5)
DIGITS = ("thumb_metacarpal", "thumb_phalanges", *(f"{finger}_{joint}" for finger in ("index", "middle", "ring", "little")
                                                    for joint in ("proximal", "distal")))
SIDES = {"l": "left", "r": "right"}  # the skeleton's _l is the body's left (MakeHuman's .L)

Rule = Literal["owner", "most weight", "dominant bone", "muscle joint", "within"]


@dataclass(frozen=True)
class Split:
    """One way of dividing the body: its groups (name → part names) and the rule placing a vertex."""

    rule: Rule
    groups: Mapping[str, tuple[str, ...]]
    where: str  # the module that uses it


def _limbs(side: str) -> dict[str, tuple[str, ...]]:
    """One side's limb groups as the contact tests part them (suffix `_l`/`_r`)."""
    return {
        f"shoulder_{side}": _sided(side, "clavicle", "scapula"),
        f"upper_arm_{side}": _sided(side, "upper_arm"),
        f"forearm_{side}": _sided(side, "forearm"),
        f"hand_{side}": _sided(side, "hand", *DIGITS),
        f"thigh_{side}": _sided(side, "thigh"),
        f"shank_{side}": _sided(side, "shank"),
        f"foot_{side}": _sided(side, "foot", "toes"),
    }


def _zones(side: str) -> dict[str, tuple[str, ...]]:
    """One side's joint zones (`measure.zones`), by the parts their skin lies on."""
    return {
        f"shoulder_{SIDES[side]}": (*_sided(side, "clavicle", "scapula", "upper_arm"), *THORACIC[:7]),
        f"elbow_{SIDES[side]}": _sided(side, "upper_arm", "forearm"),
        f"knee_{SIDES[side]}": _sided(side, "thigh", "shank"),
    }


LIMB_PARTS = ("upper_arm", "forearm", "hand", *DIGITS, "thigh", "shank", "foot", "toes")
ALL_PARTS = ("pelvis", *LUMBAR, *THORACIC, *CERVICAL, "head", "jaw",
             *(part for side in SIDES for part in _sided(side, "clavicle", "scapula", *LIMB_PARTS)))
BACK = (*THORACIC, *LUMBAR, "cervical_7")
SEAT = ("pelvis", "thigh_l", "thigh_r")
STRAIN_ZONES = {"back": BACK, "seat": SEAT, **_zones("r"), **_zones("l")}

SPLITS: dict[str, Split] = {
    "contact groups": Split("most weight", {
        "head": ("head", "jaw"),
        "neck": CERVICAL,
        # T10-T12 are the chest's, T9 the abdomen's: the cut the self-contact test's answers stand on
        "chest": (*THORACIC[:8], *THORACIC[9:]),
        "abdomen": ("thoracic_9", *LUMBAR[:3]),
        "pelvis": ("lumbar_4", "lumbar_5", "pelvis"),
        **_limbs("l"), **_limbs("r"),
    }, "hitogata.skin.contact"),
    "rest contact groups": Split("dominant bone", {
        "trunk": ("pelvis", *LUMBAR, *THORACIC),
        "neck": CERVICAL,
        "head": ("head", "jaw"),
        **_limbs("l"), **_limbs("r"),
    }, "hitogata.body.rest_contact"),
    "fit regions": Split("dominant bone", {
        "head and neck": (*CERVICAL, "head", "jaw"),
        "trunk": ("pelvis", *LUMBAR, *THORACIC, *_sided("l", "clavicle", "scapula"), *_sided("r", "clavicle", "scapula")),
        **{f"{name} {limb}": _sided(side, *parts)
           for limb, parts in (("arm", ("upper_arm", "forearm")), ("hand", ("hand", *DIGITS)),
                               ("leg", ("thigh", "shank")), ("foot", ("foot", "toes")))
           for side, name in SIDES.items()},
    }, "hitogata.made_to_measure.scan_fit.regions"),
    "muscle folders": Split("muscle joint", {
        "Trunk": (*LUMBAR, *THORACIC, "pelvis"),
        "Neck and jaw": (*CERVICAL, "head", "jaw"),
        **{f"{name.capitalize()} {region}": _sided(side, *parts)
           for side, name in SIDES.items()
           for region, parts in (("shoulder", ("clavicle", "scapula", "upper_arm")),
                                 ("elbow and forearm", ("forearm",)), ("wrist", ("hand",)),
                                 ("thumb", DIGITS[:2]), ("fingers", DIGITS[2:]), ("hip", ("thigh",)),
                                 ("knee", ("shank",)), ("ankle and toes", ("foot", "toes")))},
    }, "hitogata.viewer.groups"),
    "strain zones": Split("within", STRAIN_ZONES, "hitogata.measure.zones"),
    "garment zones": Split("within", {
        "across_back": (*THORACIC, "lumbar_1", "upper_arm_l", "upper_arm_r"),
        "across_front": (*THORACIC, "lumbar_1", *(p for s in SIDES for p in _sided(s, "clavicle", "scapula", "upper_arm"))),
        "shoulder": STRAIN_ZONES["shoulder_right"],
        "upper_arm": ("upper_arm_r",),
        "elbow": STRAIN_ZONES["elbow_right"],
        "seat": SEAT,
        "waist": (*THORACIC[9:], *LUMBAR),
        "thigh": ("thigh_r",),
        "knee": STRAIN_ZONES["knee_right"],
    }, "hitogata.garment.stretch"),
    "tape skin": Split("within", {
        **{girth: tuple(p for p in ALL_PARTS if not p.startswith(("forearm", "hand", *DIGITS, "shank", "foot", "toes")))
           for girth in ("chest_girth", "underbust_girth", "waist_girth", "omphalion_waist_girth",
                         "iliac_crest_waist_girth", "hip_girth")},
        "thigh_girth": ("pelvis", "lumbar_5", "thigh_r"),
        "upper_arm_girth": ("upper_arm_r",),
        "knee_girth": ("thigh_r", "shank_r"),
        "calf_girth": ("shank_r",),
        "ankle_girth": ("shank_r", "foot_r"),
        "wrist_girth": ("forearm_r", "hand_r"),
    }, "hitogata.measure.measurements"),
}


def part_groups(split: str, names: Sequence[str]) -> np.ndarray:
    """(parts,) the group (index into the split's groups) of each part name, -1 for a part it does not name.

    >>> part_groups("contact groups", ("pelvis", "forearm_l", "index_distal_r")).tolist()
    [4, 7, 15]
    """
    group_of = {part: g for g, parts in enumerate(SPLITS[split].groups.values()) for part in parts}
    return np.array([group_of.get(name, -1) for name in names], dtype=np.intp)


def owning_parts(weights: sp.spmatrix | np.ndarray) -> np.ndarray:
    """(V,) each row's owning column: the part holding most of a skin vertex's (V, parts) skinning weight (or
    of any non-negative weights by row), the first stored of equal largest ones, as scipy's `argmax(axis=1)`
    answers, in one pass over the stored weights (scipy's loops row by row: 0.1 s on a body's FE nodes)."""
    matrix = sp.csr_matrix(weights)
    if not matrix.has_canonical_format:
        matrix = matrix.copy()
        matrix.sum_duplicates()
    counts = np.diff(matrix.indptr)
    rows = np.flatnonzero(counts)
    out = np.zeros(matrix.shape[0], dtype=np.intp)
    if not len(rows):
        return out
    top = np.maximum.reduceat(matrix.data, matrix.indptr[rows])
    row_of = np.repeat(np.arange(matrix.shape[0]), counts)
    largest = np.full(matrix.shape[0], np.nan)
    largest[rows] = top
    hit = np.flatnonzero(matrix.data == largest[row_of])
    first_rows, first = np.unique(row_of[hit], return_index=True)
    out[first_rows] = matrix.indices[hit[first]]
    implicit = rows[(top <= 0) & (counts[rows] < matrix.shape[1])]  # an unstored zero may be the largest
    if len(implicit):
        out[implicit] = np.asarray(matrix[implicit].argmax(axis=1)).ravel()
    return out


def vertex_parts(body: Body) -> np.ndarray:
    """(V,) each skin vertex's owning part (index into the shipped skeleton's parts), found once per body
    and kept with it."""
    return body.prepared(find_vertex_parts)


def find_vertex_parts(body: Body) -> np.ndarray:
    """(V,) the owning part of each skin vertex of the body's poser (`poser_for`)."""
    return owning_parts(poser_for(body).skin.weights)


def bone_carriers(poser: Poser) -> np.ndarray:
    """(B,) the part carrying each rig bone: the part its skinning weight goes to, and for a bone the skeleton
    shares along the spine and neck (`[[shared]]`: no one part) the part carrying its joint centre."""
    part_of, _ = bone_parts(poser.skeleton, poser.body.rig)
    return np.where(part_of >= 0, part_of, poser.rig_parts)


def dominant_bone_parts(poser: Poser) -> np.ndarray:
    """(V,) per skin vertex, the part carrying its dominant rig bone (the bone of largest skinning weight)."""
    return bone_carriers(poser)[owning_parts(poser.body.skin_weights)]


def mainly_weighted(body: Body, bones: Sequence[int]) -> np.ndarray:
    """(V,) bool: the skin vertices whose summed skinning weight on the rig bones `bones` (indices) is at
    least MAIN_WEIGHT: the skin that mainly follows them."""
    return np.asarray(body.skin_weights[:, list(bones)].sum(axis=1)).ravel() >= MAIN_WEIGHT
