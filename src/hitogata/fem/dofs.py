"""Degrees of freedom: node-major numbering (dof = 3 * node + component) and Dirichlet sets.

Bone nodes are attached to the skeleton, so their three displacements are
prescribed; everything else is solved for on the remaining "free" dofs.
"""

from __future__ import annotations

import numpy as np

from hitogata.errors import HitogataError


def node_dofs(nodes: np.ndarray) -> np.ndarray:
    """The 3 dofs of each node, flattened in node order: (3 * len(nodes),)."""
    nodes = np.asarray(nodes, dtype=np.int64).ravel()
    return (3 * nodes[:, None] + np.arange(3)).ravel()


def check_nodes(nodes: np.ndarray | list[int] | None, n_nodes: int, what: str = "fixed node") -> np.ndarray:
    """Validated, sorted, unique int64 node indices (empty for None)."""
    if nodes is None:
        return np.zeros(0, dtype=np.int64)
    arr = np.asarray(nodes)
    if arr.size == 0:
        return np.zeros(0, dtype=np.int64)
    if not np.issubdtype(arr.dtype, np.integer):
        raise HitogataError(f"{what} indices have dtype {arr.dtype}; allowed: integers 0..{n_nodes - 1}")
    bad = arr[(arr < 0) | (arr >= n_nodes)]
    if bad.size:
        raise HitogataError(f"{what} index {int(bad.ravel()[0])} is out of range; allowed: 0..{n_nodes - 1}")
    return np.unique(arr.astype(np.int64))


def constrained_dofs(n_dofs: int, fixed_nodes: np.ndarray | list[int] | None = None,
                     fixed_dofs: np.ndarray | list[int] | None = None) -> np.ndarray:
    """Sorted unique dofs fixed either as whole nodes or one by one."""
    if n_dofs % 3:
        raise HitogataError(f"matrix size {n_dofs} is not 3 x nodes; allowed: 3 dofs per node")
    nodes = node_dofs(check_nodes(fixed_nodes, n_dofs // 3))
    single = check_nodes(fixed_dofs, n_dofs, what="fixed dof")
    return np.union1d(nodes, single)


def free_dofs(n_dofs: int, fixed_nodes: np.ndarray | list[int] | None = None,
              fixed_dofs: np.ndarray | list[int] | None = None) -> np.ndarray:
    """Sorted dofs that are not constrained."""
    mask = np.ones(n_dofs, dtype=bool)
    mask[constrained_dofs(n_dofs, fixed_nodes, fixed_dofs)] = False
    return np.flatnonzero(mask)
