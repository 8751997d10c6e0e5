"""MakeHuman skinning weights (163 bones) mapped onto the skeleton's parts.

A bone listed in a part's `bones` gives that part its weights; a bone listed
nowhere gives them to the part of its nearest listed ancestor (face bones to
the head, toe bones to the toes). Bones of a `[[shared]]` group (the rig's five
spine and three neck bones) give their weights to a chain of parts by where
the vertex lies along the chain — its coordinate along the chain's overall
direction (for the spine: its height) — each part's weight being a hat
function centred on the middle of its span, so the skin bends smoothly across
every vertebra. Every vertex keeps its whole weight: rows still sum to 1.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from hitogata.errors import HitogataError
from hitogata.body.rig import Rig
from hitogata.skeleton.placement import Skeleton


def bone_parts(skeleton: Skeleton, rig: Rig) -> tuple[np.ndarray, dict[int, int]]:
    """Part of every rig bone (-1 for shared ones) and, for shared bones, their group."""
    spec = skeleton.spec
    part_of = np.full(len(rig.names), -2, dtype=np.int64)
    group_of: dict[int, int] = {}
    for i, p in enumerate(spec.parts):
        for bone in p.bones:
            if bone not in rig.names:
                raise HitogataError(f"{spec.source}: part {p.name!r}: unknown rig bone {bone!r}")
            part_of[rig.index(bone)] = i
    for g, s in enumerate(spec.shared):
        for bone in s.bones:
            if bone not in rig.names:
                raise HitogataError(f"{spec.source}: shared {g}: unknown rig bone {bone!r}")
            part_of[rig.index(bone)] = -1
            group_of[rig.index(bone)] = g
    for b in range(len(rig.names)):
        k = b
        while part_of[k] == -2 and rig.parents[k] >= 0:
            k = int(rig.parents[k])
        if part_of[k] == -2:
            raise HitogataError(
                f"{spec.source}: rig bone {rig.names[b]!r} gets no part: list it or an ancestor in a part's bones"
            )
        if part_of[b] == -2:
            part_of[b] = part_of[k]
            if k in group_of:
                group_of[b] = group_of[k]
    return part_of, group_of


def hat_weights(s: np.ndarray, nodes: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Linear interpolation between increasing nodes: (left index, right index, right weight)."""
    s = np.clip(s, nodes[0], nodes[-1])
    right = np.clip(np.searchsorted(nodes, s, side="right"), 1, len(nodes) - 1)
    left = right - 1
    gap = nodes[right] - nodes[left]
    return left, right, np.where(gap > 0, (s - nodes[left]) / np.where(gap > 0, gap, 1.0), 0.0)


def part_weights(skeleton: Skeleton, rig: Rig, weights: sp.spmatrix, vertices: np.ndarray) -> sp.csr_matrix:
    """(V, N) skinning weights over the skeleton's parts, rows summing to 1.

    `weights` is the body's (V, B) rig weights, `vertices` its (V, 3) rest skin.
    """
    w = sp.csr_matrix(weights)
    n_parts = len(skeleton.names)
    part_of, group_of = bone_parts(skeleton, rig)
    direct = part_of >= 0
    mapping = sp.csr_matrix(
        (np.ones(direct.sum()), (np.flatnonzero(direct), part_of[direct])), shape=(len(rig.names), n_parts)
    )
    result = (w @ mapping).tocsr()
    for g, shared in enumerate(skeleton.spec.shared):
        bones = [b for b, grp in group_of.items() if grp == g]
        total = np.asarray(w[:, bones].sum(axis=1)).ravel()
        rows = np.flatnonzero(total > 0)
        if not len(rows):
            continue
        chain = np.array([skeleton.index(n) for n in shared.parts])
        ends = np.vstack([skeleton.joints[chain], skeleton.tails[chain[-1]]])
        direction = (ends[-1] - ends[0]) / np.linalg.norm(ends[-1] - ends[0])
        nodes = 0.5 * (ends[:-1] + ends[1:]) @ direction
        if np.any(np.diff(nodes) <= 0):
            raise HitogataError(f"{skeleton.spec.source}: shared {g}: its parts must run one way along the chain")
        left, right, t = hat_weights(vertices[rows] @ direction, nodes)
        share = sp.csr_matrix(
            (
                np.concatenate([total[rows] * (1 - t), total[rows] * t]),
                (np.concatenate([rows, rows]), np.concatenate([chain[left], chain[right]])),
            ),
            shape=result.shape,
        )
        result = result + share
    result.eliminate_zeros()
    sums = np.asarray(result.sum(axis=1)).ravel()
    return (sp.diags(1.0 / sums) @ result).tocsr()
