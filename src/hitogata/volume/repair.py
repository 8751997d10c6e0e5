"""Make a stuffed mesh one well-held body: no pinches, no loose or hinged pieces.

Isosurface stuffing meshes a smooth domain whose features are larger than the
lattice; where a bone capsule comes within a fraction of an element of the
skin or of another capsule (elbow, knee, ankle, wrist, face), the soft tissue
between them is thinner than the lattice resolves and the stuffed mesh can
pinch there: tets joined to the rest by an edge or a vertex only, a
non-manifold boundary, islands of a few tets hanging on one or two capsule
nodes. `repair` removes exactly those tets, in rounds until none is left:

1. round every vertex and every edge, the tets fall into groups joined through
   faces holding it; where there are several, the largest group (most tets)
   stays and the others' tets round that vertex or edge go;
2. every face-connected piece whose held nodes do not span a triangle at least
   `MIN_HOLD_WIDTH` high (`integrity.hold_width`) goes: it would float or hinge.

Removing a tet can pinch its neighbours, hence the rounds. What goes is
tissue thinner than the lattice next to a bone (measured: see docs/elastic.md);
the skin there follows the skeleton through the skin map.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.geometry.unique import unique_rows
from hitogata.volume.integrity import MIN_HOLD_WIDTH, TET_EDGES, boundary_fans, face_pieces, hold_width, star_groups
from hitogata.volume.lattice import TetMesh
from hitogata.volume.quality import boundary_faces, signed_volumes

_MAX_ROUNDS = 50  # a round removes the pinches it finds; the body needs a handful


@dataclass(frozen=True)
class Repair:
    """What `repair` did (volume m³)."""

    split: int  # held nodes copied, one copy per extra group of tets round them
    pinched: int  # tets removed at pinched vertices or edges, or at a vertex with several boundary fans
    unheld: int  # tets removed in pieces not held across `MIN_HOLD_WIDTH`
    removed_volume: float
    rounds: int


def repair(mesh: TetMesh, held: np.ndarray) -> tuple[TetMesh, Repair]:
    """The mesh with every vertex and edge joined through faces, a 2-manifold boundary, and every
    piece held across `MIN_HOLD_WIDTH` by its nodes in `held` (indices of nodes following the skeleton).

    A held node where groups of tets meet only at it is split: each group gets its own
    copy, which follows the same bone (the node is fixed, so nothing hinges there).
    Elsewhere the tets of all but the largest group go (module note).
    """
    nodes, part, tets = mesh.nodes, mesh.node_part, mesh.tets
    is_held = np.zeros(len(nodes), dtype=bool)
    is_held[held] = True
    split = pinched = unheld = 0
    volume = 0.0
    for rounds in range(1, _MAX_ROUNDS + 1):  # noqa: B007 (the count is reported after the loop)
        tets, copies = _split_held(tets, is_held)
        nodes, part, is_held = nodes[np.r_[np.arange(len(nodes)), copies]], part[np.r_[np.arange(len(part)), copies]], \
            is_held[np.r_[np.arange(len(is_held)), copies]]
        split += len(copies)
        drop = _minor_groups(tets, np.arange(4)[:, None]) | _minor_groups(tets, TET_EDGES) | _minor_fans(tets)
        pinched += int(drop.sum())
        piece = face_pieces(tets)
        for k in np.unique(piece[~drop]):
            mine = ~drop & (piece == k)
            corners = np.unique(tets[mine])
            if hold_width(nodes[corners[is_held[corners]]]) < MIN_HOLD_WIDTH:
                drop |= mine
                unheld += int(mine.sum())
        volume += float(signed_volumes(nodes, tets[drop]).sum())
        tets = tets[~drop]
        if not drop.any() and not len(copies):
            break
    used = np.unique(tets)
    renumber = np.full(len(nodes), -1, dtype=np.int64)
    renumber[used] = np.arange(len(used))
    return (TetMesh(nodes=nodes[used], tets=renumber[tets], node_part=part[used]),
            Repair(split=split, pinched=pinched, unheld=unheld, removed_volume=volume, rounds=rounds))


def _split_held(tets: np.ndarray, is_held: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Give each extra face-joined group of tets round a held node its own copy of the node.

    Returns the renumbered tets and, for each new node (numbered after the existing
    ones), the node it copies.
    """
    keys, key, group = star_groups(tets, np.arange(4)[:, None])
    vertex = keys.ravel()[key]  # per incidence 4 t + c
    pairs = unique_rows(np.stack([vertex, group], axis=1))
    extra = np.r_[False, pairs[1:, 0] == pairs[:-1, 0]] & is_held[pairs[:, 0]]
    if not extra.any():
        return tets, np.empty(0, dtype=np.int64)
    new_id = np.full(group.max() + 1, -1, dtype=np.int64)
    new_id[pairs[extra, 1]] = len(is_held) + np.arange(int(extra.sum()))
    tets = tets.copy().ravel()
    moved = new_id[group] >= 0
    tets[moved] = new_id[group[moved]]
    return tets.reshape(-1, 4), pairs[extra, 0]


def _minor_fans(tets: np.ndarray) -> np.ndarray:
    """(T,) True for the tets at a vertex whose boundary triangles form several fans that own a
    triangle of any fan but the largest there (the vertex's tets are joined, its boundary is not)."""
    faces, owner = boundary_faces(tets)
    fan = boundary_fans(faces)
    vertex = faces.ravel()
    size = np.bincount(fan)
    order = np.lexsort((fan, -size[fan], vertex))
    first = np.r_[True, vertex[order][1:] != vertex[order][:-1]]
    best = np.full(vertex.max() + 1, -1, dtype=np.int64)
    best[vertex[order][first]] = fan[order][first]
    drop = np.zeros(len(tets), dtype=bool)
    drop[owner[np.flatnonzero(fan != best[vertex]) // 3]] = True
    return drop


def _minor_groups(tets: np.ndarray, local: np.ndarray) -> np.ndarray:
    """(T,) True for the tets in all but the largest face-joined group round some vertex or edge."""
    _, key, group = star_groups(tets, local)
    size = np.bincount(group)
    # The largest group of each simplex (ties: the lower group label).
    order = np.lexsort((group, -size[group], key))
    first = np.r_[True, key[order][1:] != key[order][:-1]]
    best = np.empty(key.max() + 1, dtype=np.int64)
    best[key[order][first]] = group[order][first]
    minor = group != best[key]
    drop = np.zeros(len(tets), dtype=bool)
    drop[np.flatnonzero(minor) // len(local)] = True
    return drop

