"""The skeleton's skinning carried into the elastic body: part weights at every FE node.

The gross motion of the tissue is skinning, evaluated at the FE nodes, so the
weights must live there too:

- nodes on the skin take the part weights of the body's nearest skin vertices
  (inverse-distance blend of the 4 nearest), the weights an artist's rig gives;
- bone nodes take their rig bone's part (the spine's rig bones are shared
  among the vertebrae by height, as for the skin), so they move rigidly
  with their part;
- every other node is harmonic: the graph-Laplacian interpolation between
  those two, which keeps the weights in [0, 1], summing to 1 and smooth
  through the depth of the tissue;
- quadratic (P2) mid-edge nodes take the mean of their edge's ends.

The body's skin is bound to the nodes with those same part weights
(`NodeRig.skin_map`): each skin vertex only to tets of the mesh's body piece
whose corners move with the vertex's own parts (`elastic.mapping`), never to
a loose piece or to another limb across a gap.

Per pose, `NodeRig.pose` gives the skinned node positions and a rotation per
node (the normalised blend of the parts' quaternions, the rotation DQS
uses): the local frame in which the elastic correction is computed.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components
import scipy.sparse.linalg as sla
from scipy.spatial import cKDTree

from hitogata.geometry.rotations import quaternion_matrices
from hitogata.elastic.mapping import DEFAULT_FADE, skin_reach, skin_vertex_map
from hitogata.errors import HitogataError
from hitogata.fem.elements import P2_EDGES
from hitogata.options import Skinning
from hitogata.posing.pose import Poser
from hitogata.posing.body_split import owning_parts
from hitogata.skeleton.weights import part_weights
from hitogata.posing.skinning import Skin, dual_quaternions, prepare_skin, skin_vertices

if TYPE_CHECKING:
    from hitogata.elastic import ElasticModel

SKIN_NEIGHBOURS = 4
# For binding the skin, the vertebrae within this many places along the spine chain count as
# one part: the skin's weights are shared among them by height, and neighbours move alike.
CHAIN_WINDOW = 3
RIGID = 0.99  # a bone node whose largest part weight reaches this moves with that part alone


@dataclass(frozen=True, eq=False)
class NodeRig:
    """FE nodes prepared for skinning by the skeleton's parts."""

    skin: Skin  # rest = the FE nodes
    method: Skinning
    skin_map: sp.csr_matrix | None = None  # (V, N): the body's skin vertices bound to the nodes (see module note)

    @property
    def weights(self) -> sp.csr_matrix:
        """(N, parts) part weights, rows summing to 1."""
        return self.skin.weights

    def pose(self, rotations: np.ndarray, translations: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Skinned nodes (P, N, 3) and node rotations (P, N, 3, 3) for part rotations and translations."""
        x = skin_vertices(self.skin, rotations, translations, self.method)
        return x, self.rotations(rotations, translations)

    def rotations(self, rotations: np.ndarray, translations: np.ndarray) -> np.ndarray:
        """(P, N, 3, 3) node rotations: the blended, normalised part quaternions."""
        dq = dual_quaternions(self.skin, rotations, translations)[..., :4]  # (P, parts, 4), hemispheres aligned
        q = np.stack([self.skin.weights @ d for d in dq])
        q /= np.linalg.norm(q, axis=-1, keepdims=True)
        return quaternion_matrices(q)


def node_weights(poser: Poser, volume, points: np.ndarray, elements: np.ndarray,
                 fixed_nodes: np.ndarray, fixed_bone: np.ndarray) -> sp.csr_matrix:
    """(N, parts) part weights of the FE nodes (see the module note).

    volume: the `VolumeModel` (its P1 nodes are the first nodes of `points`);
    fixed_nodes/fixed_bone: bone nodes and their rig bone (index into volume.bone_names).
    """
    corners = len(volume.nodes)
    if not np.allclose(points[:corners], volume.nodes):
        raise HitogataError("elastic model: its first nodes must be the volume mesh's nodes")
    body, sk = poser.body, poser.skeleton
    n_parts = len(sk.names)

    skin_nodes = np.unique(volume.boundary_faces[volume.boundary_on_skin])
    skin_w = nearest_skin_weights(poser, volume.nodes[skin_nodes])

    bone = fixed_nodes < corners
    bone_nodes, bone_of = fixed_nodes[bone], np.asarray(fixed_bone)[bone]
    rig = body.rig
    rig_cols = np.array([rig.index(volume.bone_names[b]) for b in bone_of], dtype=np.int64)
    one_hot = sp.csr_matrix((np.ones(len(bone_nodes)), (np.arange(len(bone_nodes)), rig_cols)),
                            shape=(len(bone_nodes), len(rig.names)))
    bone_w = part_weights(sk, rig, one_hot, volume.nodes[bone_nodes])

    known = np.zeros((corners, n_parts))
    is_known = np.zeros(corners, dtype=bool)
    known[skin_nodes] = skin_w.toarray()
    known[bone_nodes] = bone_w.toarray()  # a node both on the skin and on a bone follows the bone
    is_known[skin_nodes] = True
    is_known[bone_nodes] = True
    w = _harmonic(volume.tets, known, is_known)

    if elements.shape[1] == 10:
        mids = elements[:, 4:].ravel()
        ends = elements[:, P2_EDGES].reshape(-1, 2)
        full = np.zeros((len(points), n_parts))
        full[:corners] = w
        full[mids] = 0.5 * (w[ends[:, 0]] + w[ends[:, 1]])
        w = full
    w[w < 1e-6] = 0.0
    w /= w.sum(axis=1, keepdims=True)
    return sp.csr_matrix(w)


def nearest_skin(poser: Poser, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The body's SKIN_NEIGHBOURS nearest skin vertices of each point (P, k) and their inverse-distance
    shares (P, k), summing to 1."""
    dist, near = cKDTree(poser.body.vertices).query(points, k=SKIN_NEIGHBOURS)
    idw = 1.0 / np.maximum(dist, 1e-6)
    return near, idw / idw.sum(axis=1, keepdims=True)


def nearest_skin_weights(poser: Poser, points: np.ndarray) -> sp.csr_matrix:
    """(P, parts) part weights of points: those of their nearest skin vertices, blended (`nearest_skin`)."""
    near, idw = nearest_skin(poser, points)
    part_w = poser.skin.weights
    return sp.csr_matrix(sum(sp.diags(idw[:, j]) @ part_w[near[:, j]] for j in range(SKIN_NEIGHBOURS)))


def _harmonic(tets: np.ndarray, known: np.ndarray, is_known: np.ndarray) -> np.ndarray:
    """Values at unknown nodes solving the graph Laplace equation with the known nodes fixed."""
    n = len(known)
    a, b = tets[:, [0, 0, 0, 1, 1, 2]].ravel(), tets[:, [1, 2, 3, 2, 3, 3]].ravel()
    adj = sp.csr_matrix((np.ones(2 * len(a)), (np.concatenate([a, b]), np.concatenate([b, a]))), shape=(n, n))
    adj.data[:] = 1.0
    lap = (sp.diags(np.asarray(adj.sum(axis=1)).ravel()) - adj).tocsr()
    free = np.flatnonzero(~is_known)
    out = known.copy()
    if len(free):
        fixed = np.flatnonzero(is_known)
        rhs = -(lap[free][:, fixed] @ known[fixed])
        out[free] = sla.splu(lap[free][:, free].tocsc()).solve(np.ascontiguousarray(rhs))
    return np.clip(out, 0.0, None)


def joint_nodes(weights: sp.csr_matrix, elements: np.ndarray, fixed_nodes: np.ndarray) -> np.ndarray:
    """Bone nodes sharing an element with a bone node of another part: the joints' "cartilage".

    Only nodes carried rigidly by one part count (the spine's nodes, blended
    between neighbouring vertebrae, bend smoothly). An element with nodes on
    two parts that rotate apart (elbow, knee, hip, shoulder) cannot keep from
    inverting, so the quasi-statics lets these nodes settle between the bones.
    """
    top = np.asarray(weights.max(axis=1).todense()).ravel()
    part = owning_parts(weights)
    rigid = np.zeros(weights.shape[0], dtype=bool)
    rigid[fixed_nodes] = True
    rigid &= top >= RIGID
    corners = elements[:, :4]
    parts = np.where(rigid[corners], part[corners], -1)
    high = parts.max(axis=1)
    low = np.where(parts >= 0, parts, high[:, None]).min(axis=1)
    mixed = corners[low != high]
    return np.unique(mixed[rigid[mixed]])


def anchored(held: np.ndarray, fixed_nodes: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """`held` plus the bone nodes of every piece of mesh (corners joined through elements) that holds none
    of them: a piece hanging on its joints' nodes alone (once those settle freely) floats, the
    quasi-statics' matrix is singular there, and round-off alone places it (a tetrahedron of the default
    male's, thrown 1.1 m in a step). Other pieces keep their joints free: holding joint nodes rigid can
    invert an element in a deep crease."""
    n = int(corners.max()) + 1
    pairs = np.stack([np.repeat(corners[:, :1], corners.shape[1], axis=1).ravel(), corners.ravel()])
    graph = sp.csr_matrix((np.ones(pairs.shape[1], dtype=np.int8), (pairs[0], pairs[1])), shape=(n, n))
    _, piece = connected_components(graph, directed=False)
    fixed = np.asarray(fixed_nodes)
    fixed = fixed[fixed < n]
    bare = np.setdiff1d(piece[fixed], piece[held[held < n]])
    return np.union1d(held, fixed[np.isin(piece[fixed], bare)])


def node_rig(poser: Poser, model: ElasticModel, method: Skinning = "dqs", bind_skin: bool = True) -> NodeRig:
    """The elastic model's nodes prepared for skinning by the poser's skeleton ('lbs' or 'dqs');
    bind_skin: also bind the body's skin to the nodes that move with its parts (`skin_map`)."""
    if method not in ("lbs", "dqs"):
        raise HitogataError(f"skinning = {method!r}: allowed lbs, dqs")
    w = node_weights(poser, model.volume, model.points, model.elements, model.fixed_nodes, model.fixed_bone)
    skin_map = None
    if bind_skin:
        volume = model.volume
        reach = skin_reach(volume.quality.surface_distance_max, volume.element_size)
        blur = chain_blur(poser.skeleton)
        skin_map = skin_vertex_map(poser.body.vertices, model.points, model.elements, reach, DEFAULT_FADE,
                                   poser.skin.weights @ blur, w @ blur)
    return NodeRig(prepare_skin(model.points, w, poser.skeleton.parents), method, skin_map)


def chain_blur(skeleton) -> sp.csr_matrix:
    """(parts, parts) row-stochastic: each part of a shared chain (the spine) spread evenly over the
    chain's parts within CHAIN_WINDOW places of it; every other part stays itself.

    Weights multiplied by it compare by what moves alike: a neck vertex weighted to C4 and a
    node on C2's capsule agree, a thigh and the other thigh do not."""
    n = len(skeleton.names)
    rows, cols = list(range(n)), list(range(n))
    for shared in skeleton.spec.shared:
        chain = [skeleton.names.index(p) for p in shared.parts]
        for i, a in enumerate(chain):
            for b in chain[max(0, i - CHAIN_WINDOW):i + CHAIN_WINDOW + 1]:
                if b != a:
                    rows.append(a)
                    cols.append(b)
    blur = sp.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n))
    return sp.diags(1.0 / np.asarray(blur.sum(axis=1)).ravel()) @ blur
