"""Uniform refinement of a labelled tet mesh, for convergence studies at fixed geometry.

Refining the lattice (a smaller element size) also moves the region
boundaries, the bone capsules and the skin layer, so frequencies then change
for two reasons. Splitting every tet into eight keeps the geometry, the
labels and the constrained nodes, and isolates the discretisation error.
The refined mesh's nodes are exactly the P2 nodes of the original (corners,
then edge midpoints), so P1 on the refined mesh and P2 on the original have
the same degrees of freedom.
"""

from __future__ import annotations

import numpy as np

from hitogata.fem import lift_node_set, p2_mesh

# Local P2 node numbers (elements.P2_EDGES order): 4 = m01, 5 = m12, 6 = m02, 7 = m03, 8 = m13, 9 = m23.
_CORNER_TETS = np.array([[0, 4, 6, 7], [4, 1, 5, 8], [6, 5, 2, 9], [7, 8, 9, 3]])
# The inner octahedron split along one of its three diagonals: (diagonal, the ring of four round it).
_DIAGONALS = (((4, 9), (6, 5, 8, 7)), ((6, 8), (4, 5, 9, 7)), ((7, 5), (4, 8, 9, 6)))


def refine(points: np.ndarray, tets: np.ndarray, labels: np.ndarray,
           nodes: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Split each tet into eight (positively oriented), children keep their parent's label.

    `nodes` (a node set of the original, e.g. the fixed bone nodes) is carried
    over with the midpoints of edges between two of its nodes. The inner
    octahedron is cut along its shortest diagonal (the best-shaped children).
    Returns (points, tets (8T, 4), labels (8T,), nodes).
    """
    points2, tets2 = p2_mesh(points, tets)
    x = points2[tets2]
    lengths = np.stack([np.linalg.norm(x[:, a] - x[:, b], axis=1) for (a, b), _ in _DIAGONALS], axis=1)
    choice = lengths.argmin(axis=1)
    children = [tets2[:, c] for c in _CORNER_TETS]
    inner = np.empty((len(tets2), 4, 4), dtype=tets2.dtype)
    for k, ((a, b), ring) in enumerate(_DIAGONALS):
        mine = choice == k
        for j in range(4):
            inner[mine, j] = tets2[mine][:, [a, b, ring[j], ring[(j + 1) % 4]]]
    fine = np.concatenate([np.stack(children, axis=1), inner], axis=1).reshape(-1, 4)
    p = points2[fine]
    volume = np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]))
    fine[volume < 0] = fine[volume < 0][:, [0, 1, 3, 2]]
    return points2, fine, np.repeat(np.asarray(labels), 8), lift_node_set(tets2, nodes)
