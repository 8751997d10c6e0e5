"""Nodal force vectors (n_dofs,) for the load f of K u = f and M u'' + C u' + K u = f.

Muscle activation is an eigenstrain: a strain eps0 the tissue would take if
it were free (like thermal expansion). Its equivalent nodal forces are
f = integral of B^T D eps0 = integral of grad(N_a) . sigma0, sigma0 = D eps0,
so that an unconstrained body deforms by exactly eps0 with zero stress.

Sign convention: strain is positive in extension. A muscle's contraction c
is positive when it shortens, so its fibre strain is eps = -c along the fibre
direction d; stretching a muscle (e.g. the rectus abdominis when the trunk
extends) is a negative contraction.
"""

from __future__ import annotations

import numpy as np

from hitogata.errors import HitogataError
from hitogata.fem.elements import (
    MATERIAL_SAMPLES,
    check_mesh,
    element_order,
    quadrature,
    shape_gradients,
    shape_values,
    tet_geometry,
)
from hitogata.fem.materials import check_material, lame, per_element, per_sample
from hitogata.geometry.normals import triangle_areas


def fibre_eigenstrain(directions: np.ndarray, strain: float | np.ndarray, isochoric: bool = False) -> np.ndarray:
    """Eigenstrain tensors (T, 3, 3) of a strain along fibre directions (T, 3).

    Uniaxial: eps (d x d). Isochoric: eps (d x d - (I - d x d) / 2), the fibre
    shortening while the cross-section thickens at constant volume, as muscle
    does; prefer it for nearly incompressible tissue (nu -> 0.5), where a
    volume-changing eigenstrain meets a very large bulk stiffness.
    """
    d = np.atleast_2d(np.asarray(directions, dtype=float))
    norm = np.linalg.norm(d, axis=1)
    if d.shape[1] != 3 or not np.all(norm > 0) or not np.all(np.isfinite(d)):
        raise HitogataError("fibre directions are invalid; allowed: finite non-zero 3-vectors, shape (T, 3)")
    d = d / norm[:, None]
    eps = np.broadcast_to(np.asarray(strain, dtype=float), (len(d),))
    dd = np.einsum("ti,tj->tij", d, d)
    shape = 1.5 * dd - 0.5 * np.eye(3) if isochoric else dd
    return eps[:, None, None] * shape


def muscle_eigenstrain(directions: np.ndarray, contraction: float | np.ndarray, isochoric: bool = True) -> np.ndarray:
    """Eigenstrain of a muscle contraction (positive = shortening, negative = stretch): fibre strain -contraction."""
    return fibre_eigenstrain(directions, -np.asarray(contraction, dtype=float), isochoric=isochoric)


def eigenstrain_load(points: np.ndarray, tets: np.ndarray, E: float | np.ndarray, nu: float | np.ndarray,
                     strain: np.ndarray, elements: np.ndarray | None = None) -> np.ndarray:
    """Equivalent nodal forces of eigenstrains in the selected tets.

    ``elements`` (indices or a boolean mask, default all) selects the tets
    that carry ``strain``: (len(elements), 3, 3), constant in each tet, or
    (len(elements), Q, 3, 3), one per material sample point
    (`elements.MATERIAL_SAMPLES`; zero where the tissue has none, e.g. a
    muscle's edge inside a tet). E and nu: global, per element of the whole
    mesh (T,), or per sample point (T, Q). Per tet: f_a = integral of
    sigma0 . grad N_a, exact with the centroid rule for a constant sigma0
    (gradients are at most linear), else on the sample points.
    """
    points = np.asarray(points, dtype=float)
    tets = np.asarray(tets)
    check_mesh(points, tets)
    sel = np.arange(len(tets)) if elements is None else np.arange(len(tets))[np.asarray(elements)]
    bary, weights = MATERIAL_SAMPLES
    E_all = per_sample(len(tets), len(weights), E, "E")
    nu_all = per_sample(len(tets), len(weights), nu, "nu")
    check_material(E_all, nu_all)
    eps = np.asarray(strain, dtype=float)
    if eps.shape not in ((len(sel), 3, 3), (len(sel), len(weights), 3, 3)):
        raise HitogataError(f"eigenstrain has shape {eps.shape}; allowed: ({len(sel)}, 3, 3), one per selected tet, "
                            f"or ({len(sel)}, {len(weights)}, 3, 3), one per sample point")
    per_point = eps.ndim == 4 or E_all.shape[1] > 1 or nu_all.shape[1] > 1
    if not per_point:
        bary, weights = quadrature(0)
    eps = np.broadcast_to(eps if eps.ndim == 4 else eps[:, None], (len(sel), len(weights), 3, 3))
    eps = 0.5 * (eps + np.swapaxes(eps, 2, 3))
    lam, mu = lame(*np.broadcast_arrays(E_all[sel], nu_all[sel]))
    trace = np.trace(eps, axis1=2, axis2=3)
    sigma = (lam * trace)[..., None, None] * np.eye(3) + 2 * mu[..., None, None] * eps  # (n, Q, 3, 3)
    order = element_order(tets)
    grads_l, vol = tet_geometry(points, tets[sel])
    gradients = shape_gradients(order, bary, grads_l)  # (n, Q, nodes, 3)
    forces = np.einsum("q,tqij,tqaj->tai", weights, sigma, gradients) * vol[:, None, None]
    return _scatter(tets[sel], forces, len(points))


def gravity_load(points: np.ndarray, tets: np.ndarray, rho: float | np.ndarray,
                 g: tuple[float, float, float] = (0.0, -9.81, 0.0)) -> np.ndarray:
    """Nodal forces of the body's weight: integral of rho g N_a (default g: 9.81 m/s^2 along -Y, the frame's down).

    For P2 tets the corner nodes get a small negative share (-1/20 of the
    tet's weight) and edge nodes 1/5 each: the exact consistent load.
    """
    points = np.asarray(points, dtype=float)
    tets = np.asarray(tets)
    check_mesh(points, tets)
    rho = per_element(len(tets), rho, "rho")
    check_material(1.0, 0.0, rho)
    order = element_order(tets)
    bary, w = quadrature(order)
    share = w @ shape_values(order, bary)  # integral of N_a / V
    _, vol = tet_geometry(points, tets)
    weight = (rho * vol)[:, None, None] * share[None, :, None] * np.asarray(g, dtype=float)
    return _scatter(tets, weight, len(points))


def nodal_load(n_nodes: int, nodes: np.ndarray, forces: np.ndarray) -> np.ndarray:
    """Point forces (len(nodes), 3) or one (3,) for all, in N, applied at the given nodes."""
    nodes = np.atleast_1d(np.asarray(nodes))
    if nodes.size and (not np.issubdtype(nodes.dtype, np.integer) or nodes.min() < 0 or nodes.max() >= n_nodes):
        raise HitogataError(f"load node indices {nodes.min()}..{nodes.max()} are invalid; allowed: 0..{n_nodes - 1}")
    f = np.zeros((n_nodes, 3))
    np.add.at(f, nodes, np.broadcast_to(np.asarray(forces, dtype=float), (len(nodes), 3)))
    return f.ravel()


def traction_load(points: np.ndarray, faces: np.ndarray, traction: np.ndarray) -> np.ndarray:
    """Nodal forces of a surface traction (Pa), constant per face, on boundary triangles.

    faces: (F, 3) linear or (F, 6) quadratic triangles (corners, then the
    midpoints of edges 01, 12, 20), e.g. from ``elements.boundary_faces``.
    traction: (3,) for all faces or (F, 3). A linear triangle gives each
    corner 1/3 of the force; a quadratic one gives the corners 0 and each
    edge node 1/3 (the exact integrals of the shape functions).
    """
    points = np.asarray(points, dtype=float)
    faces = np.asarray(faces)
    if faces.ndim != 2 or faces.shape[1] not in (3, 6):
        raise HitogataError(f"faces have shape {faces.shape}; allowed: (F, 3) or (F, 6) node indices")
    if faces.size and (faces.min() < 0 or faces.max() >= len(points)):
        raise HitogataError(f"face node index out of range; allowed: 0..{len(points) - 1}")
    x = points[faces[:, :3]]
    area = triangle_areas(x)
    share = np.full(3, 1.0 / 3.0) if faces.shape[1] == 3 else np.array([0, 0, 0, 1, 1, 1]) / 3.0
    t = np.broadcast_to(np.asarray(traction, dtype=float), (len(faces), 3))
    return _scatter(faces, area[:, None, None] * share[None, :, None] * t[:, None, :], len(points))


def _scatter(cells: np.ndarray, forces: np.ndarray, n_nodes: int) -> np.ndarray:
    """Sum per-cell nodal forces (C, n, 3) into a global vector (3 n_nodes,)."""
    f = np.zeros((n_nodes, 3))
    for i in range(3):
        f[:, i] = np.bincount(cells.ravel(), weights=forces[..., i].ravel(), minlength=n_nodes)
    return f.ravel()
