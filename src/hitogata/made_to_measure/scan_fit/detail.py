"""Per-vertex detail: a small, smooth offset of each skin vertex along its normal, and the body it makes.

What the shape parameters cannot reach is taken up by one signed distance per
skin vertex along the rest surface's normal, solved by sparse least squares:
the scan points' distances from the posed surface (each spread over its
triangle's corners by barycentric weights), a graph-Laplacian smoothness term
(`hitogata.geometry.shells.smoothing_operator`) and a small pull towards zero
that keeps unseen skin (holes) where the model put it; then capped at
`DETAIL_CAP`. Being along the normal, the offset is the same at rest and in a
pose (LBS carries the normal with the skin), so it is solved on the posed scan
and stored with the body at rest: `detailed_body` rebuilds the fitted body from
its shape parameters and the offsets, which is all a body file needs to hold.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from hitogata.body.assets import load_assets
from hitogata.body.model import WHOLE_BODY_DENSITY, Body
from hitogata.body.shape import ShapeParameters
from hitogata.errors import HitogataError
from hitogata.geometry.normals import vertex_normals
from hitogata.geometry.shells import smoothing_operator
from hitogata.made_to_measure.scan_fit.closest import signed_closest

DETAIL_CAP = 0.010  # m: no vertex moves further than this from the model's surface
SMOOTHNESS = 4.0  # Laplacian weight, per scan point a vertex has on average
TO_ZERO = 0.02  # pull towards no offset, per scan point a vertex has on average
REACH = 0.03  # m: scan points further than this from the body are not detail (outliers, other parts)
QUANTUM = 1e-5  # m: offsets are kept to 0.01 mm, as the body file stores them


def solve_detail(posed: np.ndarray, faces: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(n_surface,) offsets (m, outward positive) that bring the posed surface (V, 3) onto the scan points (P, 3)."""
    from scipy.sparse.linalg import spsolve  # here: rebuilding a fitted body's detail needs no solver

    n_surface = load_assets().n_surface
    near, signed = signed_closest(posed, faces, points)
    used = np.abs(signed) < REACH
    corners = faces[near.face[used]]
    n = len(posed)
    rows = np.repeat(np.arange(np.count_nonzero(used)), 3)
    data = sp.csr_matrix((near.bary[used].ravel(), (rows, corners.ravel())), shape=(np.count_nonzero(used), n))
    per_vertex = max(np.count_nonzero(used) / n, 1.0)
    laplacian = smoothing_operator(n, faces)
    system = (data.T @ data + SMOOTHNESS * per_vertex * (laplacian.T @ laplacian)
              + TO_ZERO * per_vertex * sp.identity(n)).tocsc()
    offsets = spsolve(system, data.T @ signed[used])
    capped = np.clip(offsets[:n_surface], -DETAIL_CAP, DETAIL_CAP)
    return np.round(capped / QUANTUM) * QUANTUM


def detailed_body(params: ShapeParameters, offsets: np.ndarray | None,
                  density: float = WHOLE_BODY_DENSITY) -> Body:
    """The body of the shape parameters with each skin vertex moved by its offset along the rest normal.

    The rig is placed on the moved vertices as on any body (`Body.rig`), so the
    skin weights, skeleton and muscles follow the detail.
    """
    body = Body.from_parameters(params, density)
    if offsets is None:
        return body
    n_surface = load_assets().n_surface
    offsets = np.asarray(offsets, dtype=np.float64)
    if offsets.shape != (n_surface,):
        raise HitogataError(f"detail offsets of shape {offsets.shape}: allowed ({n_surface},), one per skin vertex")
    normals = vertex_normals(body.vertices, body.faces)[:n_surface]
    moved = body.all_vertices.copy()
    moved[:n_surface] += offsets[:, None] * normals
    return Body(params, moved, density)


def detail_offsets(body: Body) -> np.ndarray | None:
    """(n_surface,) a body's offsets from its shape parameters' surface along the rest normals; None if it has none."""
    plain = Body.from_parameters(body.params, body.density)
    n_surface = load_assets().n_surface
    moved = body.all_vertices[:n_surface] - plain.all_vertices[:n_surface]
    if not np.any(moved):
        return None
    normals = vertex_normals(plain.vertices, plain.faces)[:n_surface]
    return np.einsum("ij,ij->i", moved, normals)
