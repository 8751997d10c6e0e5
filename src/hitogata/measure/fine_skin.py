"""A skin fine enough to measure: the MakeHuman skin subdivided, carried like the skin itself.

The MakeHuman skin's edges are 15–28 mm at the elbow and 14–33 mm at the
knee, so a 10 cm line crosses five to seven triangles and a strain field on
it is a set of flat bands. The fine skin splits every triangle into four
(edge midpoints) `LEVELS` times — 16 triangles per triangle, edges a quarter
as long — once per body. Its rest surface is the coarse one (midpoints of flat
triangles), but it is posed by the same skinning with the skin weights
interpolated to its vertices, so inside a coarse triangle the skinned surface
bends as the blended bone transforms do rather than staying flat; an elastic
displacement of the coarse skin (the elastic body's correction) is carried to
it by the same interpolation. The coarse mesh stays the simulation surface.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from hitogata.body import Body
from hitogata.measure.topology import topology
from hitogata.options import Skinning
from hitogata.skeleton.kinematics import Pose
from hitogata.skinning import Skin, prepare_skin, skin_vertices

LEVELS = 2  # edge ÷ 4: ≥ 20 triangles crossed by a 10 cm line at the elbow and the knee


@dataclass(frozen=True, eq=False)
class FineSkin:
    """A subdivided surface: rest vertices, faces, and how each vertex lies on the coarse one."""

    vertices: np.ndarray  # (Vf, 3) rest
    faces: np.ndarray  # (Ff, 3)
    interpolation: sp.csr_matrix  # (Vf, V): fine vertex = combination of coarse vertices (rows sum to 1)
    parent: np.ndarray  # (Ff,) the coarse face each fine face lies in

    def carry(self, coarse: np.ndarray) -> np.ndarray:
        """A per-vertex field of the coarse skin (V, k) interpolated onto the fine one (Vf, k)."""
        return np.asarray(self.interpolation @ coarse)


def subdivide(vertices: np.ndarray, faces: np.ndarray, levels: int = LEVELS) -> FineSkin:
    """Midpoint subdivision: every triangle into four, `levels` times."""
    n0 = len(vertices)
    interp = sp.identity(n0, format="csr")
    parent = np.arange(len(faces))
    v, f = np.asarray(vertices, dtype=float), np.asarray(faces, dtype=np.int64)
    for _ in range(levels):
        topo = topology(f)
        n, e = len(v), len(topo.edges)
        rows = np.concatenate([np.arange(n), np.repeat(n + np.arange(e), 2)])
        cols = np.concatenate([np.arange(n), topo.edges.ravel()])
        vals = np.concatenate([np.ones(n), np.full(2 * e, 0.5)])
        step = sp.csr_matrix((vals, (rows, cols)), shape=(n + e, n))
        a, b, c = f.T
        ab, bc, ca = (n + topo.face_edges).T  # edges v0v1, v1v2, v2v0
        f = np.concatenate([np.stack(t, axis=1) for t in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))])
        parent = np.tile(parent, 4)
        v = step @ v
        interp = step @ interp
    return FineSkin(v, f, sp.csr_matrix(interp), parent)


_BY_BODY: weakref.WeakKeyDictionary[Body, FineSkin] = weakref.WeakKeyDictionary()


def fine_skin(body: Body) -> FineSkin:
    """The body's fine skin, built once per body."""
    found = _BY_BODY.get(body)
    if found is None:
        found = _BY_BODY[body] = subdivide(body.vertices, body.faces)
    return found


@dataclass(frozen=True, eq=False)
class FineSkinning:
    """The fine skin prepared for skinning with the coarse skin's part weights, interpolated."""

    fine: FineSkin
    skin: Skin
    coarse: Skin

    def surface(self, pose: Pose, method: Skinning = "lbs", coarse_vertices: np.ndarray | None = None) -> np.ndarray:
        """(Vf, 3) the fine skin of one pose (P = 1): skinned, plus the interpolated difference between
        `coarse_vertices` (e.g. the elastic skin) and the coarse skin skinned the same way."""
        r, t = pose.rotations[:1], pose.translations[:1]
        out = skin_vertices(self.skin, r, t, method)[0]
        if coarse_vertices is not None:
            out = out + self.fine.carry(np.asarray(coarse_vertices) - skin_vertices(self.coarse, r, t, method)[0])
        return out


_BY_SKIN: weakref.WeakKeyDictionary[Skin, FineSkinning] = weakref.WeakKeyDictionary()


def fine_skinning(body: Body, coarse: Skin) -> FineSkinning:
    """The fine skin of `body` with the part weights of `coarse` (a `Poser.skin`), built once per skin."""
    found = _BY_SKIN.get(coarse)
    if found is None:
        fine = fine_skin(body)
        weights = sp.csr_matrix(fine.interpolation @ coarse.weights)
        found = _BY_SKIN[coarse] = FineSkinning(fine, prepare_skin(fine.vertices, weights, coarse.parents), coarse)
    return found
