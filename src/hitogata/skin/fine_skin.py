"""A skin fine enough to measure: the MakeHuman skin subdivided, carried like the skin itself.

The MakeHuman skin's edges are 15–28 mm at the elbow and 14–33 mm at the
knee, so a 10 cm line crosses five to twelve triangles and a strain field on
it is a set of flat bands. The fine skin is the skin Loop-subdivided
`LEVELS` times — 16 triangles per triangle, edges about a quarter as long —
once per body. Loop's stencils smooth the rest surface and, applied to the
skin weights and to an elastic displacement of the coarse skin (the elastic
body's correction), make both vary smoothly across the coarse triangles' edges
too, so the posed fine skin's stretch is smooth where the coarse one is a
patchwork of per-triangle values (midpoint subdivision would keep the
weights' piecewise-linear kinks and the bands). It is posed by the same
skinning with those weights. The coarse mesh stays the simulation surface.
A body posed elastically keeps its fine skin and the fine skin's weights in the
disk cache (`hitogata.disk_cache`, keyed by the body and the code) beside its
elastic model (`keep_fine_skin`): a second process reads them instead of
subdividing again. Other bodies' are made in the process that asks (a body
measured once would only fill the cache).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from hitogata.body.model import Body
from hitogata.geometry.strain import RestFrames, rest_frames
from hitogata.geometry.topology import topology
from hitogata.options import Skinning
from hitogata.posing.pose import poser_for
from hitogata.skeleton.kinematics import Pose
from hitogata.posing.skinning import Skin, prepare_skin, skin_vertices

LEVELS = 2  # edge ÷ 4: ≥ 20 triangles crossed by a 10 cm line at the elbow and the knee
FINE_SKIN = "fine-skin"  # the disk cache's entry kind
FORMAT = 1  # raised when what the entry holds, or how, changes


@dataclass(frozen=True, eq=False)
class FineSkin:
    """A subdivided surface: rest vertices, faces, and how each vertex lies on the coarse one."""

    vertices: np.ndarray  # (Vf, 3) rest
    faces: np.ndarray  # (Ff, 3)
    interpolation: sp.csr_matrix  # (Vf, V): fine vertex = combination of coarse vertices (rows sum to 1)
    parent: np.ndarray  # (Ff,) the coarse face each fine face lies in

    @cached_property
    def rest_frames(self) -> RestFrames:
        """Each rest triangle in its own plane (`geometry.strain.rest_frames`): found once, strained against
        at every posture."""
        return rest_frames(self.vertices, self.faces)

    def carry(self, coarse: np.ndarray) -> np.ndarray:
        """A per-vertex field of the coarse skin (V, k) interpolated onto the fine one (Vf, k)."""
        return np.asarray(self.interpolation @ coarse)


def subdivide(vertices: np.ndarray, faces: np.ndarray, levels: int = LEVELS) -> FineSkin:
    """Loop subdivision: every triangle into four, `levels` times; positions and any per-vertex field
    (weights, displacements) through the same linear stencils (`FineSkin.interpolation`)."""
    interp = sp.identity(len(vertices), format="csr")
    parent = np.arange(len(faces))
    f = np.asarray(faces, dtype=np.int64)
    for _ in range(levels):
        step, f = _loop_step(f, interp.shape[0])
        parent = np.tile(parent, 4)
        interp = step @ interp
    interp = sp.csr_matrix(interp)
    return FineSkin(np.asarray(interp @ np.asarray(vertices, dtype=float)), f, interp, parent)


def _loop_step(faces: np.ndarray, n: int) -> tuple[sp.csr_matrix, np.ndarray]:
    """One Loop step (Loop 1987, Warren's weights): the (n + E, n) stencil matrix and the new faces.

    Edge point: 3/8 of each end + 1/8 of each opposite corner (an edge without two faces: its
    midpoint); vertex point: (1 − k β) of itself + β of each of its k neighbours, β = 3/16 for
    k = 3, else 3/(8k).
    """
    topo = topology(faces)
    e = len(topo.edges)
    a, b, c = faces.T
    ab, bc, ca = topo.face_edges.T  # edges v0v1, v1v2, v2v0; opposite corners c, a, b
    edge_ids = np.concatenate([ab, bc, ca])
    opposite = np.concatenate([c, a, b])
    count = np.bincount(edge_ids, minlength=e)
    inner = count[edge_ids] == 2
    two = count == 2
    ends = np.where(two, 3.0 / 8.0, 0.5)
    rows = [np.repeat(n + np.arange(e), 2), n + edge_ids[inner]]
    cols = [topo.edges.ravel(), opposite[inner]]
    vals = [np.repeat(ends, 2), np.full(inner.sum(), 1.0 / 8.0)]
    k = np.bincount(topo.edges.ravel(), minlength=n).astype(float)
    beta = np.where(k == 3, 3.0 / 16.0, 3.0 / (8.0 * np.maximum(k, 1.0)))
    rows += [np.arange(n), topo.edges[:, 0], topo.edges[:, 1]]
    cols += [np.arange(n), topo.edges[:, 1], topo.edges[:, 0]]
    vals += [1.0 - k * beta, beta[topo.edges[:, 0]], beta[topo.edges[:, 1]]]
    step = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n + e, n))
    m_ab, m_bc, m_ca = n + ab, n + bc, n + ca
    new = np.concatenate([np.stack(t, axis=1) for t in ((a, m_ab, m_ca), (m_ab, b, m_bc), (m_ca, m_bc, c),
                                                        (m_ab, m_bc, m_ca))])
    return step, new


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


def fine_skinning(fine: FineSkin, coarse: Skin, weights: sp.csr_matrix | None = None,
                  homogeneous: sp.csr_matrix | None = None) -> FineSkinning:
    """The fine skin prepared for skinning with the part weights of `coarse` (a `Poser.skin`)
    interpolated (`body_fine_skinning` is the body's own); `weights` and `homogeneous`: those found before
    for this fine skin and these weights (read from the disk cache), else found here."""
    if weights is None or homogeneous is None:
        weights = sp.csr_matrix(fine.interpolation @ coarse.weights)
        return FineSkinning(fine, prepare_skin(fine.vertices, weights, coarse.parents), coarse)
    skin = Skin(fine.vertices, weights, homogeneous, coarse.parents, coarse.ancestors,  # the same tree as `coarse`
                np.ascontiguousarray(fine.vertices.T))
    return FineSkinning(fine, skin, coarse)


def body_fine_skin(body: Body) -> FineSkin:
    """The body's skin subdivided `LEVELS` times, found once per body and kept with it (read from the disk
    cache where `keep_fine_skin` stored it)."""
    return body.prepared(_stored_fine_skin)[0]


def body_fine_skinning(body: Body) -> FineSkinning:
    """The body's fine skin prepared for skinning with its poser's part weights, once per body."""
    return body.prepared(_fine_skinning_of_body)


def keep_fine_skin(body: Body) -> None:
    """Store the body's fine skin and its weights in the disk cache unless they are there or the cache is off
    (`hitogata.disk_cache`), once per body and process: for a body posed elastically, whose every posture
    carries it."""
    body.prepared(_keep_fine_skin)


def _keep_fine_skin(body: Body) -> bool:
    from hitogata import disk_cache

    key = _key(body)
    if disk_cache.enabled() and not disk_cache.entry_path(FINE_SKIN, key).exists():
        skinning = body_fine_skinning(body)
        disk_cache.save(FINE_SKIN, key, _encode((skinning.fine, skinning.skin.weights, skinning.skin.homogeneous)))
    return True


def _key(body: Body) -> dict[str, object]:
    from hitogata.elastic.cache import body_digest, code_digest

    return {"format": FORMAT, "code": code_digest(), "body": body_digest(body), "levels": LEVELS}


def _stored_fine_skin(body: Body) -> tuple[FineSkin, sp.csr_matrix | None, sp.csr_matrix | None]:
    """The body's fine skin with its skinning's weights and homogeneous weights (`Skin`): read from the disk
    cache where `keep_fine_skin` stored them for this body and code, else the fine skin made (the weights
    then made when skinning asks for them: `body_fine_skinning`)."""
    from hitogata import disk_cache

    stored = disk_cache.read_cached(FINE_SKIN, _key(body), _decode) if disk_cache.enabled() else None
    return (subdivide(body.vertices, body.faces), None, None) if stored is None else stored


def _encode(value: tuple[FineSkin, sp.csr_matrix, sp.csr_matrix]) -> dict[str, np.ndarray]:
    from hitogata.elastic.stored import to_arrays

    fine, weights, homogeneous = value
    return to_arrays({"vertices": fine.vertices, "faces": fine.faces, "interpolation": fine.interpolation,
                      "parent": fine.parent, "weights": weights, "homogeneous": homogeneous})


def _decode(arrays: Mapping[str, np.ndarray]) -> tuple[FineSkin, sp.csr_matrix, sp.csr_matrix]:
    from hitogata.elastic.stored import from_arrays

    parts = from_arrays(arrays)
    fine = FineSkin(parts["vertices"], parts["faces"], parts["interpolation"], parts["parent"])
    return fine, parts["weights"], parts["homogeneous"]


def _fine_skinning_of_body(body: Body) -> FineSkinning:
    fine, weights, homogeneous = body.prepared(_stored_fine_skin)
    return fine_skinning(fine, poser_for(body).skin, weights, homogeneous)
