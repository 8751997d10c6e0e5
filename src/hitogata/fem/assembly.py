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

from hitogata.errors import HitogataError
from hitogata.fem.elements import (
    MATERIAL_SAMPLES,
    check_mesh,
    element_order,
    quadrature,
    reference_mass,
    shape_gradients,
    shape_values,
    tet_geometry,
)
from hitogata.fem.materials import check_material, lame, per_element, per_sample

_CHUNK_ENTRIES = 2**20  # element-matrix node pairs per vectorised batch: bounds temporary memory
# How the volumetric term lambda (div u)(div v) is integrated: pointwise ("full", the plain
# displacement element) or on each element's mean dilatation ("mean").
from hitogata.options import DILATATIONS  # noqa: E402  (owned there)


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
                     pattern: Pattern | None = None, dilatation: str = "full") -> sp.csr_matrix:
    """Stiffness K of isotropic linear elasticity.

    E (Pa) and nu: global, per element (T,), or per material sample point (T, Q)
    (`elements.MATERIAL_SAMPLES`: a material that varies inside the elements,
    as at tissue interfaces). Element entry for nodes a, b, components i, j:
    integral of  lambda dNa_i dNb_j + mu dNa_j dNb_i + mu delta_ij grad Na . grad Nb.

    dilatation "full" integrates the lambda term pointwise: the plain
    displacement element. "mean" takes it on each element's mean dilatation:
    a pressure constant per element, condensed (the P2-P0 mixed element, or
    Hughes' B-bar; Nagtegaal, Parks & Rice 1974, Comput Methods Appl Mech Eng
    4:153), with lambda's harmonic mean over the element. P2 tets lock mildly
    as nu -> 0.5 (the trunk's tissue at nu 0.49 is 3 % too stiff at 40 mm);
    "mean" removes that. For P1 tets, whose dilatation is constant, both agree
    where the material is uniform in the element.
    """
    points = np.asarray(points, dtype=float)
    tets = np.asarray(tets)
    check_mesh(points, tets)
    if dilatation not in DILATATIONS:
        raise HitogataError(f"dilatation {dilatation!r}: allowed {', '.join(DILATATIONS)}")
    n_samples = len(MATERIAL_SAMPLES[1])
    E = per_sample(len(tets), n_samples, E, "E")
    nu = per_sample(len(tets), n_samples, nu, "nu")
    check_material(E, nu)
    lam, mu = lame(*np.broadcast_arrays(E, nu))
    pattern = pattern or sparsity(tets, len(points))
    return pattern.assemble(lambda batch: _stiffness_blocks(points, tets[batch], lam[batch], mu[batch], dilatation))


def mass_matrix(points: np.ndarray, tets: np.ndarray, rho: float | np.ndarray, lumped: bool = False,
                pattern: Pattern | None = None) -> sp.csr_matrix:
    """Mass M with density rho (kg/m^3) per element or global: consistent (exact) or lumped.

    Lumped mass uses diagonal scaling (HRZ): each element's mass is shared
    among its nodes in proportion to the diagonal of its consistent mass. For
    P2 tets this keeps every nodal mass positive (row sums would give the
    corners negative mass); for P1 it equals the row sum, V/4 per node.
    Consistent M is stored on the stiffness pattern (explicit zeros between
    different components) so it can be combined with K array-wise. rho may
    also be given per material sample point (T, Q), as E in `stiffness_matrix`
    (lumped mass then uses each element's mean).
    """
    points = np.asarray(points, dtype=float)
    tets = np.asarray(tets)
    check_mesh(points, tets)
    weights = MATERIAL_SAMPLES[1]
    rho = per_sample(len(tets), len(weights), rho, "rho")
    check_material(1.0, 0.0, rho)
    if lumped:
        return sp.diags(lumped_masses(points, tets, rho @ weights if rho.shape[1] > 1 else rho[:, 0])).tocsr()
    pattern = pattern or sparsity(tets, len(points))
    order = element_order(tets)
    _, vol = tet_geometry(points, tets)
    if rho.shape[1] == 1:
        ref = reference_mass(order)

        def blocks_of(batch: slice) -> dict[tuple[int, int], np.ndarray]:
            block = (rho[batch, 0] * vol[batch])[:, None, None] * ref
            return {(i, i): block for i in range(3)}
    else:
        n = shape_values(order, MATERIAL_SAMPLES[0])

        def blocks_of(batch: slice) -> dict[tuple[int, int], np.ndarray]:
            block = np.einsum("tq,qa,qb->tab", rho[batch] * weights * vol[batch, None], n, n)
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


def _stiffness_blocks(points: np.ndarray, tets: np.ndarray, lam: np.ndarray, mu: np.ndarray, dilatation: str
                      ) -> dict[tuple[int, int], np.ndarray]:
    """Element stiffness blocks K[(i, j)] (T, n, n) for a batch of tets; lam, mu (T, 1) or (T, Q)."""
    order = element_order(tets)
    # Uniform material: the rule exact for the element (1 point for P1, 4 for P2); varying: its samples.
    bary, w = quadrature(2 * (order - 1)) if lam.shape[1] == 1 else MATERIAL_SAMPLES
    grads_l, vol = tet_geometry(points, tets)
    g = shape_gradients(order, bary, grads_l)  # (T, Q, n, 3)
    a_mu = _gram(g, mu * w * vol[:, None])  # (T, 3, 3, n, n)
    if dilatation == "mean":
        mean = shape_gradients(order, np.full((1, 4), 0.25), grads_l)[:, 0]  # gradients are linear: the mean
        with np.errstate(divide="ignore"):  # nu = 0 somewhere: lambda 0 there, and so its harmonic mean
            lam_mean = lam[:, 0] if lam.shape[1] == 1 else 1.0 / (w / lam).sum(axis=1)
        a_lam = _gram(mean[:, None], (lam_mean * vol)[:, None])
    else:
        a_lam = _gram(g, lam * w * vol[:, None])
    trace = a_mu[:, 0, 0] + a_mu[:, 1, 1] + a_mu[:, 2, 2]
    return {(i, j): a_lam[:, i, j] + a_mu[:, j, i] + (trace if i == j else 0.0) for i in range(3) for j in range(3)}


def _gram(g: np.ndarray, weight: np.ndarray) -> np.ndarray:
    """Sum over points q of weight[t, q] g[t, q, a, i] g[t, q, b, j], as (T, 3, 3, n, n); exactly
    symmetric under (i, a) <-> (j, b) (the weight's root goes into both factors), so K is too."""
    root = g * np.sqrt(weight)[:, :, None, None]
    return np.einsum("tqai,tqbj->tijab", root, root)
