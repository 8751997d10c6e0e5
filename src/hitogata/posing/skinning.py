"""Skinning the body surface with a posed skeleton: linear blend and dual quaternions.

Both are vectorised over vertices and poses with the sparse (V, N) part
weights. Linear blend skinning (LBS) is written as one sparse product of the
rest positions' weighted homogeneous coordinates (V, 4N) with the stacked
transforms minus identity (4N, 3P), so the rest pose gives the rest surface
exactly and a batch of poses is a single product. Dual-quaternion skinning
(DQS, Kavan et al. 2008) blends unit dual quaternions instead, which keeps
twisting and bending limbs from collapsing ("candy wrapper"); quaternion signs
are made consistent along the tree first (each part in its parent's hemisphere:
the sign flips along a part's path from the root, counted by one product with
the tree's ancestor matrix).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from hitogata.errors import HitogataError
from hitogata.geometry.rotations import matrix_to_quaternion
from hitogata.options import SKINNING as METHODS
from hitogata.options import Skinning

CHUNK = 64  # poses per block: bounds the (V, 8·chunk) intermediates


@dataclass(frozen=True, eq=False)
class Skin:
    """A rest surface with its part weights, prepared for skinning."""

    rest: np.ndarray  # (V, 3)
    weights: sp.csr_matrix  # (V, N) rows sum to 1
    homogeneous: sp.csr_matrix  # (V, 4N): w_vk · [x, y, z, 1]
    parents: np.ndarray  # (N,)
    ancestors: np.ndarray  # (N, N): [e, c] = 1 if part e (not the root) is on the root's path to c
    rest_xyz: np.ndarray  # (3, V) the rest positions, one contiguous row per axis

    def part(self, vertices: np.ndarray) -> Skin:
        """The skin of some of its vertices (indices, in the order given): each skinned exactly as in the
        whole, at a fraction of the cost when only those are wanted."""
        return Skin(self.rest[vertices], self.weights[vertices], self.homogeneous[vertices], self.parents,
                    self.ancestors, np.ascontiguousarray(self.rest_xyz[:, vertices]))


def prepare_skin(rest: np.ndarray, weights: sp.spmatrix, parents: np.ndarray) -> Skin:
    """Prepare a rest surface (V, 3) and its (V, N) part weights for skinning."""
    w = sp.csr_matrix(weights)
    rest = np.asarray(rest, dtype=float)
    if w.shape[0] != len(rest) or w.shape[1] != len(parents):
        raise HitogataError(f"weights of shape {w.shape}: expected ({len(rest)}, {len(parents)})")
    coo = w.tocoo()
    rows = np.repeat(coo.row, 4)
    cols = (4 * coo.col[:, None] + np.arange(4)).ravel()
    vals = (coo.data[:, None] * np.column_stack([rest[coo.row], np.ones(len(coo.row))])).ravel()
    homogeneous = sp.csr_matrix((vals, (rows, cols)), shape=(len(rest), 4 * w.shape[1]))
    n = len(parents)
    ancestors = np.zeros((n, n))
    for c in range(n):
        k = c
        while parents[k] >= 0:
            ancestors[k, c] = 1.0
            k = parents[k]
    return Skin(rest, w, homogeneous, np.asarray(parents), ancestors, np.ascontiguousarray(rest.T))


def linear_blend(skin: Skin, rotations: np.ndarray, translations: np.ndarray) -> np.ndarray:
    """(P, V, 3) posed vertices by LBS from (P, N, 3, 3) rotations and (P, N, 3) translations."""
    n_pose, n_part = rotations.shape[:2]
    out = np.empty((n_pose, len(skin.rest), 3))
    for s in range(0, n_pose, CHUNK):
        r, t = rotations[s : s + CHUNK], translations[s : s + CHUNK]
        p = len(r)
        stack = np.empty((p, 3, n_part, 4))  # [p, i, k, j] = (M_pk − I)[i, j]
        stack[..., :3] = (r - np.eye(3)).transpose(0, 2, 1, 3)
        stack[..., 3] = t.transpose(0, 2, 1)
        moved = skin.homogeneous @ stack.reshape(3 * p, 4 * n_part).T
        out[s : s + p] = skin.rest + moved.reshape(-1, p, 3).transpose(1, 0, 2)
    return out


def dual_quaternions(skin: Skin, rotations: np.ndarray, translations: np.ndarray) -> np.ndarray:
    """(P, N, 8) unit dual quaternions (real w,x,y,z; dual w,x,y,z), hemispheres aligned on the tree."""
    q = matrix_to_quaternion(rotations)
    q[:, 0] *= np.where(q[:, 0, :1] < 0, -1.0, 1.0)
    against = (np.einsum("pni,pni->pn", q, q[:, np.maximum(skin.parents, 0)]) < 0).astype(float)
    q *= (1.0 - 2.0 * (np.rint(against @ skin.ancestors) % 2))[..., None]
    t = translations
    dual = 0.5 * np.stack(
        [
            -(t * q[..., 1:]).sum(axis=-1),
            t[..., 0] * q[..., 0] + t[..., 1] * q[..., 3] - t[..., 2] * q[..., 2],
            t[..., 1] * q[..., 0] + t[..., 2] * q[..., 1] - t[..., 0] * q[..., 3],
            t[..., 2] * q[..., 0] + t[..., 0] * q[..., 2] - t[..., 1] * q[..., 1],
        ],
        axis=-1,
    )  # ½ (0, t) ⊗ q
    return np.concatenate([q, dual], axis=-1)


def dual_quaternion_blend(skin: Skin, rotations: np.ndarray, translations: np.ndarray) -> np.ndarray:
    """(P, V, 3) posed vertices by DQS from (P, N, 3, 3) rotations and (P, N, 3) translations.

    With b = (r, d) the blended, unnormalised dual quaternion and s = 1/|r|²,
    v' = v + 2s (r⃗ × (r⃗ × v + r_w v + d⃗) + r_w d⃗ − d_w r⃗): Kavan's formula with
    the normalisation folded into one factor.
    """
    dq = dual_quaternions(skin, rotations, translations)
    n_pose, n_part = dq.shape[:2]
    out = np.empty((n_pose, len(skin.rest), 3))
    x, y, z = skin.rest_xyz
    for s in range(0, n_pose, CHUNK):
        block = dq[s : s + CHUNK]
        p = len(block)
        b = skin.weights @ block.transpose(1, 2, 0).reshape(n_part, 8 * p)  # (V, 8p), columns (c, p)
        rw, rx, ry, rz, dw, dx, dy, dz = b.T.reshape(8, p, -1)
        cx = ry * z - rz * y + rw * x + dx
        cy = rz * x - rx * z + rw * y + dy
        cz = rx * y - ry * x + rw * z + dz
        scale = 2.0 / (rw * rw + rx * rx + ry * ry + rz * rz)
        res = out[s : s + p]
        res[..., 0] = x + scale * (ry * cz - rz * cy + rw * dx - dw * rx)
        res[..., 1] = y + scale * (rz * cx - rx * cz + rw * dy - dw * ry)
        res[..., 2] = z + scale * (rx * cy - ry * cx + rw * dz - dw * rz)
    return out


def skin_vertices(skin: Skin, rotations: np.ndarray, translations: np.ndarray, method: Skinning = "lbs") -> np.ndarray:
    """(P, V, 3) posed surface by 'lbs' or 'dqs'."""
    if method == "lbs":
        return linear_blend(skin, rotations, translations)
    if method == "dqs":
        return dual_quaternion_blend(skin, rotations, translations)
    raise HitogataError(f"skinning = {method!r}: allowed {', '.join(METHODS)}")
