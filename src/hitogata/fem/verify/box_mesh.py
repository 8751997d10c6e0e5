"""A structured tetrahedral mesh of a box, for tests, benchmarks and convergence studies.

Each hexahedral cell is cut into 6 tets around its main diagonal (Kuhn
subdivision). Every cell uses the same diagonal direction, so neighbouring
cells agree on the diagonals of their shared faces and the mesh is conforming.
"""

from __future__ import annotations

from itertools import permutations

import numpy as np
import scipy.sparse as sp

from hitogata.errors import HitogataError
from hitogata.fem.assembly import mass_matrix, sparsity, stiffness_matrix
from hitogata.fem.elements import lift_node_set, p2_mesh
from hitogata.options import Dilatation


def box_mesh(
    lengths: tuple[float, float, float],
    divisions: tuple[int, int, int],
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0),
) -> tuple[np.ndarray, np.ndarray]:
    """Tets filling [origin, origin + lengths] with divisions cells along x, y, z.

    Returns points (N, 3) with N = prod(divisions + 1), node (i, j, k) at index
    (i * (ny + 1) + j) * (nz + 1) + k, and positively oriented tets (6 * cells, 4).
    """
    lengths_arr = np.asarray(lengths, dtype=float)
    div = np.asarray(divisions)
    if lengths_arr.shape != (3,) or not np.all(lengths_arr > 0) or not np.all(np.isfinite(lengths_arr)):
        raise HitogataError(f"box lengths {tuple(lengths)} are invalid; allowed: three positive finite sizes in metres")
    if div.shape != (3,) or not np.issubdtype(div.dtype, np.integer) or not np.all(div >= 1):
        raise HitogataError(f"box divisions {tuple(divisions)} are invalid; allowed: three integers >= 1")
    axes = [np.linspace(o, o + s, n + 1) for o, s, n in zip(origin, lengths_arr, div)]
    points = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    shape = div + 1

    cell = np.stack(np.meshgrid(*[np.arange(n) for n in div], indexing="ij"), axis=-1).reshape(-1, 3)
    tets = []
    for perm in permutations(range(3)):
        path = [np.zeros(3, dtype=int)]
        for axis in perm:  # walk from corner 000 to 111, one axis at a time
            step = path[-1].copy()
            step[axis] = 1
            path.append(step)
        corners = [np.ravel_multi_index((cell + p).T, shape) for p in path]
        if _parity(perm):  # odd permutations give negatively oriented tets
            corners[1], corners[2] = corners[2], corners[1]
        tets.append(np.stack(corners, axis=1))
    return points, np.concatenate(tets).astype(np.int64)


def _parity(perm: tuple[int, ...]) -> int:
    """1 for an odd permutation, 0 for an even one."""
    inversions = sum(perm[i] > perm[j] for i in range(len(perm)) for j in range(i + 1, len(perm)))
    return inversions % 2


def cantilever_system(
    divisions: tuple[int, int, int], order: int, E: float = 1e6, nu: float = 0.3, rho: float = 1000.0,
    dilatation: Dilatation = "full",
) -> tuple[sp.csr_matrix, sp.csr_matrix, np.ndarray]:
    """K, M and the clamped nodes of the reference cantilever 1 × 0.1 × 0.1 m, clamped at x = 0.

    `order` 1 (P1) or 2 (P2); the default material is the one whose first bending
    frequency Timoshenko beam theory puts at 0.50687 Hz (tests and benchmarks);
    `dilatation` as in `stiffness_matrix`.
    """
    points, tets = box_mesh((1.0, 0.1, 0.1), divisions)
    fixed = np.flatnonzero(points[:, 0] < 1e-12)
    if order == 2:
        points, tets = p2_mesh(points, tets)
        fixed = lift_node_set(tets, fixed)
    pattern = sparsity(tets, len(points))
    return (stiffness_matrix(points, tets, E, nu, pattern, dilatation), mass_matrix(points, tets, rho, pattern=pattern),
            fixed)
