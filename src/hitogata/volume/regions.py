"""Tissue regions and named muscles of the tets, built as layers under the skin.

Each tet is labelled by its centroid, in this order of precedence:

- skin: closer to the skin surface than the skin+fat thickness;
- bone: inside a capsule round a rig bone, when the bones are meshed as
  labelled lattice tets (`anatomy.capsule_radii`: at least half an element
  so every bone holds nodes at coarse sizes). By default the soft tissue is
  meshed round the capsules instead (`hitogata.volume.bones`) and no tet is bone;
- viscera: in the trunk, deeper than skin+fat+muscle wall, in front of the
  vertebral bodies (the spine axis + the spine's capsule radius: psoas and
  quadratus lumborum lie beside the spine, the kidneys in front of them), within the rib cage's width (0.85 × the half-distance between
  the shoulder joints), from the pelvic floor to the thoracic inlet. This is the
  thoracic and abdominal cavity as one region, the paper's "viscera"; the
  paravertebral gutters of the lungs (beside the spine) are left to muscle;
- muscle: everything else.

Named muscles are subsets of the muscle region placed on the trunk's
landmarks (`anatomy` gives the levels and widths), each with a fibre
direction per tet lying in the tangent plane of the nearest skin.
"""

from __future__ import annotations

import numpy as np

from hitogata.volume import anatomy as A
from hitogata.volume.trunk import TrunkLandmarks, segment_distance

# The rib cage's half-width as a fraction of the half-distance between the
# shoulder joints (chest breadth ≈ 0.174 H vs shoulder joint spacing ≈ 0.2 H:
# Drillis & Contini 1966).
RIB_CAGE_WIDTH = 0.85
# The pelvic floor lies about 5 cm below the hip joint centres (at the ischial
# tuberosities), the thoracic inlet at the base of the neck.
PELVIC_FLOOR_DROP = 0.05


def tissue_regions(centroids: np.ndarray, depth: np.ndarray, marks: TrunkLandmarks, in_trunk: np.ndarray,
                   bone_heads: np.ndarray, bone_tails: np.ndarray, bone_radii: np.ndarray,
                   skin: float, wall: float) -> np.ndarray:
    """Region id (T,) per tet (ids index `anatomy.REGIONS`)."""
    region = np.full(len(centroids), A.MUSCLE, dtype=np.int8)
    region[in_trunk & (viscera_margin(centroids, depth, marks, skin, wall) >= 0)] = A.VISCERA
    region[bone_margin(centroids, bone_heads, bone_tails, bone_radii) >= 0] = A.BONE
    region[depth < skin] = A.SKIN
    return region


def viscera_margin(points: np.ndarray, depth: np.ndarray, marks: TrunkLandmarks, skin: float,
                   wall: float) -> np.ndarray:
    """(P,) m: how far inside the thoracic and abdominal cavity each point lies (>= 0 inside, given it
    is in the trunk): the least of its margins to the cavity's bounds (module note)."""
    y = points[:, 1]
    spine = marks.spine_at(y)
    ribs = RIB_CAGE_WIDTH * 0.5 * float(np.linalg.norm(marks.shoulders[0] - marks.shoulders[1]))
    return np.minimum.reduce([
        depth - (skin + wall),
        points[:, 2] - (spine[:, 2] + A.BONE_RADII["spine"]),
        ribs - np.abs(points[:, 0] - spine[:, 0]),
        y - (marks.hip_height - PELVIC_FLOOR_DROP),
        marks.neck_height - y,
    ])


def bone_margin(points: np.ndarray, heads: np.ndarray, tails: np.ndarray, radii: np.ndarray,
                reach: float = np.inf) -> np.ndarray:
    """(P,) m: how far inside the nearest bone capsule each point lies (>= 0 inside one); -reach where
    every capsule's surface is further off than `reach` (only the capsules within it are measured)."""
    out = np.full(len(points), -reach)
    if np.isinf(reach):
        if len(heads):
            out = (radii - segment_distance(points, heads, tails)).max(axis=1)
        return out
    for head, tail, radius in zip(heads, tails, radii):
        box = np.all((points >= np.minimum(head, tail) - radius - reach)
                     & (points <= np.maximum(head, tail) + radius + reach), axis=1)
        near = np.flatnonzero(box)
        out[near] = np.maximum(out[near], radius - segment_distance(points[near], head[None], tail[None])[:, 0])
    return out


def _tangent(direction: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Unit vectors: `direction` projected onto the plane of `normal` (kept as is where that vanishes)."""
    t = direction - np.einsum("ij,ij->i", direction, normal)[:, None] * normal
    length = np.linalg.norm(t, axis=1, keepdims=True)
    plain = direction / np.linalg.norm(direction, axis=1, keepdims=True)
    return np.where(length > 1e-9, t / np.maximum(length, 1e-300), plain)


def muscle_regions(centroids: np.ndarray, region: np.ndarray, normal: np.ndarray,
                   marks: TrunkLandmarks, eligible: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Muscle id (T,) per tet (-1 none; ids index `anatomy.MUSCLES`) and fibre directions (T, 3).

    `normal` (T, 3) is the unit vector from each centroid to its nearest skin point;
    `eligible` (T,) marks the tets of the trunk and hips (not of the limbs).
    Fibres are unit vectors in named-muscle tets and zero elsewhere.
    """
    x, y, z = centroids.T
    s = marks.level(y)
    spine = marks.spine_at(y)
    lateral = x - spine[:, 0]
    left = lateral > 0
    side = np.where(left, 0, 1)  # index into the (left, right) landmark pairs
    width = np.abs(lateral)
    hip_w = marks.hip_width
    up = marks.spine_axis_at(y)
    forward = np.broadcast_to([0.0, 0.0, 1.0], centroids.shape)
    front = z >= spine[:, 2] + A.BONE_RADII["spine"]
    back = z < spine[:, 2]
    muscle = (region == A.MUSCLE) & eligible
    ids = np.full(len(centroids), -1, dtype=np.int16)
    fibres = np.zeros_like(centroids)

    def assign(mask: np.ndarray, left_name: str, right_name: str | None, direction: np.ndarray) -> None:
        mask = mask & muscle & (ids < 0)
        name = np.where(left, A.MUSCLES.index(left_name), A.MUSCLES.index(right_name or left_name))
        ids[mask] = name[mask]
        fibres[mask] = _tangent(direction[mask], normal[mask])

    rectus = (s >= 0) & (s <= A.LEVEL_XIPHOID) & (width <= A.RECTUS_HALF_WIDTH * hip_w) & front
    assign(rectus, "rectus_abdominis", None, up)

    oblique = (s >= A.LEVEL_ILIAC_CREST - 0.05) & (s <= A.LEVEL_XIPHOID) & ~back & (width > A.RECTUS_HALF_WIDTH * hip_w)
    assign(oblique, "external_oblique_l", "external_oblique_r", forward - up)  # down and forward

    pec_insertion = marks.shoulders[side] + A.PECTORALIS_INSERTION * marks.arms_dir[side]
    pectoral = (s > A.LEVEL_XIPHOID) & (s <= A.LEVEL_CLAVICLE) & front & (width >= A.STERNUM_HALF_WIDTH) \
        & (width <= np.abs(marks.shoulders[side, 0] - spine[:, 0]))
    assign(pectoral, "pectoralis_major_l", "pectoralis_major_r", pec_insertion - centroids)

    erector = (s >= A.LEVEL_LOW_BACK) & (s <= 1.0) & back & (width <= A.ERECTOR_HALF_WIDTH * hip_w)
    assign(erector, "erector_spinae_l", "erector_spinae_r", up)

    outward = np.stack([np.where(left, 1.0, -1.0), np.zeros_like(x), np.zeros_like(x)], axis=1)
    glute_insertion = marks.hips[side] + A.GLUTEUS_INSERTION_DOWN * marks.knees_dir[side] \
        + A.GLUTEUS_INSERTION_OUT * outward
    gluteal = (s >= A.LEVEL_GLUTEAL_FOLD) & (s <= A.LEVEL_ILIAC_CREST) & (z < marks.hips[side, 2]) & (width >= A.STERNUM_HALF_WIDTH)
    assign(gluteal, "gluteus_maximus_l", "gluteus_maximus_r", glute_insertion - centroids)
    return ids, fibres


def attach_bone_nodes(nodes: np.ndarray, tets: np.ndarray, region: np.ndarray,
                      bone_heads: np.ndarray, bone_tails: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Nodes of bone tets (B,) and the bone segment (B,) nearest to each."""
    bone_nodes = np.unique(tets[region == A.BONE])
    nearest = segment_distance(nodes[bone_nodes], bone_heads, bone_tails).argmin(axis=1)
    return bone_nodes, nearest
