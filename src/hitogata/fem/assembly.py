"""Vectorised assembly of stiffness K and mass M for P1/P2 tets into scipy CSR.

Degrees of freedom are node-major: dof 3 * node + component (x, y, z).
The costly part of assembly is turning element entries into a CSR matrix;
``sparsity`` does that once per mesh (a node-pair graph plus a scatter map),
after which K and M are filled with ``np.bincount`` in a fraction of the time,
e.g. when materials change. K and consistent M built on one pattern share
their structure exactly, so ``K - sigma * M`` is one array operation.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from hitogata.fem.elements import (
    check_mesh,
    element_order,
    quadrature,
    reference_mass,
    shape_gradients,
    tet_geometry,
)
from hitogata.fem.materials import check_material, lame, per_element

_CHUNK_ENTRIES = 2**20  # element-matrix node pairs per vectorised batch: bounds temporary memory


@dataclass(frozen=True)
class Pattern:
    """CSR structure of a 3-dof-per-node FE matrix on one mesh, and where element entries go.

    ``slots[t, a, b]`` is the index of node pair (tets[t, a], tets[t, b]) in the
    node graph; ``perm`` maps node-graph blocks (9 per pair, component-major)
    to positions in the CSR data array.
    """

    indptr: np.ndarray
    indices: np.ndarray
    slots: np.ndarray
    perm: np.ndarray
    n_pairs: int
    n_dofs: int

    def matrix(self, data: np.ndarray) -> sp.csr_matrix:
        """A CSR matrix with this structure and the given data array."""
        m = sp.csr_matrix((data, self.indices, self.indptr), shape=(self.n_dofs, self.n_dofs))
        m.has_sorted_indices = True
        return m

    def assemble(self, blocks_of: Callable[[slice], dict[tuple[int, int], np.ndarray]]) -> sp.csr_matrix:
        """CSR matrix from element blocks, computed batch by batch.

        ``blocks_of(elements)`` returns, for a slice of elements, a dict
        {(i, j): (t, n, n) array} of the entries coupling component i of node a
        to component j of node b; missing (i, j) are zero.
        """
        n_elements, n, _ = self.slots.shape
        step = max(1, _CHUNK_ENTRIES // (n * n))
        node_data = np.zeros((9, self.n_pairs))
        for start in range(0, n_elements, step):
            batch = slice(start, start + step)
            slots = self.slots[batch].ravel()
            for (i, j), values in blocks_of(batch).items():
                node_data[3 * i + j] += np.bincount(slots, weights=values.ravel(), minlength=self.n_pairs)
        return self.matrix(node_data.ravel()[self.perm])


def sparsity(tets: np.ndarray, n_nodes: int) -> Pattern:
    """Build the reusable CSR pattern of a mesh with ``n_nodes`` nodes (3 dofs each)."""
    tets = np.asarray(tets, dtype=np.int64)
    n = tets.shape[1]
    keys = (tets[:, :, None] * n_nodes + tets[:, None, :]).ravel()
    pairs, inverse = np.unique(keys, return_inverse=True)
    rows, cols = np.divmod(pairs, n_nodes)
    node_ptr = np.zeros(n_nodes + 1, dtype=np.int64)
    np.cumsum(np.bincount(rows, minlength=n_nodes), out=node_ptr[1:])
    degree = np.diff(node_ptr)

    # Dof row 3p+i holds, for each neighbour q of p (sorted), columns 3q..3q+2.
    indptr = np.zeros(3 * n_nodes + 1, dtype=np.int64)
    indptr[1:] = np.cumsum(np.repeat(3 * degree, 3))
    k = np.arange(len(pairs)) - node_ptr[rows]  # position of q in row p
    comp = np.arange(3)
    # position of block entry (pair s, i, j) in CSR data, laid out [i, j, s]
    pos = (9 * node_ptr[rows][None, None, :] + 3 * comp[:, None, None] * degree[rows][None, None, :]
           + 3 * k[None, None, :] + comp[None, :, None])
    indices = np.empty(9 * len(pairs), dtype=np.int64)
    indices[pos] = 3 * cols[None, None, :] + comp[None, :, None]
    perm = np.empty(9 * len(pairs), dtype=np.int64)
    perm[pos.ravel()] = np.arange(9 * len(pairs))
    index_type = np.int32 if 9 * len(pairs) < 2**31 else np.int64
    return Pattern(indptr.astype(index_type), indices.astype(index_type),
                   inverse.reshape(len(tets), n, n), perm, len(pairs), 3 * n_nodes)


def stiffness_matrix(points: np.ndarray, tets: np.ndarray, E: float | np.ndarray, nu: float | np.ndarray,
                     pattern: Pattern | None = None) -> sp.csr_matrix:
    """Stiffness K of isotropic linear elasticity, with E (Pa) and nu per element or global.

    Element entry for nodes a, b and components i, j is
    integral of  lambda dNa_i dNb_j + mu dNa_j dNb_i + mu delta_ij grad Na . grad Nb,
    evaluated exactly (1-point rule for P1, 4-point for P2).
    """
    points = np.asarray(points, dtype=float)
    tets = np.asarray(tets)
    check_mesh(points, tets)
    E = per_element(len(tets), E, "E")
    nu = per_element(len(tets), nu, "nu")
    check_material(E, nu)
    lam, mu = lame(E, nu)
    pattern = pattern or sparsity(tets, len(points))
    return pattern.assemble(lambda batch: _stiffness_blocks(points, tets[batch], lam[batch], mu[batch]))


def mass_matrix(points: np.ndarray, tets: np.ndarray, rho: float | np.ndarray, lumped: bool = False,
                pattern: Pattern | None = None) -> sp.csr_matrix:
    """Mass M with density rho (kg/m^3) per element or global: consistent (exact) or lumped.

    Lumped mass uses diagonal scaling (HRZ): each element's mass is shared
    among its nodes in proportion to the diagonal of its consistent mass. For
    P2 tets this keeps every nodal mass positive (row sums would give the
    corners negative mass); for P1 it equals the row sum, V/4 per node.
    Consistent M is stored on the stiffness pattern (explicit zeros between
    different components) so it can be combined with K array-wise.
    """
    points = np.asarray(points, dtype=float)
    tets = np.asarray(tets)
    check_mesh(points, tets)
    rho = per_element(len(tets), rho, "rho")
    check_material(1.0, 0.0, rho)
    if lumped:
        return sp.diags(lumped_masses(points, tets, rho)).tocsr()
    pattern = pattern or sparsity(tets, len(points))
    ref = reference_mass(element_order(tets))
    _, vol = tet_geometry(points, tets)
    scale = rho * vol

    def blocks_of(batch: slice) -> dict[tuple[int, int], np.ndarray]:
        block = scale[batch, None, None] * ref
        return {(i, i): block for i in range(3)}

    return pattern.assemble(blocks_of)


def lumped_masses(points: np.ndarray, tets: np.ndarray, rho: float | np.ndarray) -> np.ndarray:
    """Lumped (HRZ) mass per dof, shape (3 N,); sums to the body mass once per component."""
    tets = np.asarray(tets)
    rho = per_element(len(tets), rho, "rho")
    ref = np.diag(reference_mass(element_order(tets)))
    _, vol = tet_geometry(points, tets)
    node_mass = np.bincount(tets.ravel(), weights=((rho * vol)[:, None] * ref / ref.sum()).ravel(),
                            minlength=len(points))
    return np.repeat(node_mass, 3)


def _stiffness_blocks(points: np.ndarray, tets: np.ndarray, lam: np.ndarray, mu: np.ndarray
                      ) -> dict[tuple[int, int], np.ndarray]:
    """Element stiffness blocks K[(i, j)] (T, n, n) for a batch of tets."""
    order = element_order(tets)
    bary, w = quadrature(2 * (order - 1))
    grads_l, vol = tet_geometry(points, tets)
    g = shape_gradients(order, bary, grads_l)  # (T, Q, n, 3)
    a = np.einsum("q,tqai,tqbj->tijab", w, g, g) * vol[:, None, None, None, None]  # (T, 3, 3, n, n)
    lam_ = lam[:, None, None]
    mu_ = mu[:, None, None]
    trace = a[:, 0, 0] + a[:, 1, 1] + a[:, 2, 2]
    return {(i, j): lam_ * a[:, i, j] + mu_ * a[:, j, i] + (mu_ * trace if i == j else 0.0)
            for i in range(3) for j in range(3)}

