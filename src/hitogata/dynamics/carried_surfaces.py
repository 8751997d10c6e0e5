"""Surfaces inside the body carried through a motion as its tissue moves: the tissue regions' boundaries.

A vertex moves as a skin vertex does (`BodyDynamics.skin_offset`): skinned
by part weights, plus the nodes' elastic displacement interpolated at it.
What it is bound to depends on where it lies at rest (`CARRIERS`):

- in a tet of the elastic mesh's body piece: that tet's shape functions, and
  the nodes' part weights interpolated there, so it moves as the tissue
  around it does (on a held bone's capsule, rigidly with its bone);
- outside the mesh deep in the body (in a held bone capsule's hole, a gap the
  mesh's repair left): the nearest tet's, faded out with the distance
  (`elastic.mapping.skin_vertex_map`), whatever the nearest skin moves with
  (deep in the chest that may be the armpit's skin, weighted to the arm);
- outside the mesh near the skin (the layer a lattice leaves under the skin,
  the hands, feet and thin limbs a 40 mm lattice hardly holds, a trunk
  model's limbs): the binding of its nearest skin vertices
  (`NodeRig.skin_map`: only tissue that moves with them, faded out beyond
  the mesh), blended by inverse distance.

Where the mesh's share fades, the nearest skin's part weights take the rest.
Then each vertex's weights and elastic binding are averaged with its
neighbours' over a few millimetres (`BLEND_STEPS`), so where two carriers
meet (or a joint's bones part) the surface stretches instead of tearing.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import igl
import numpy as np
import scipy.sparse as sp

from hitogata.dynamics.rigging import nearest_skin
from hitogata.elastic.mapping import DEFAULT_FADE, body_piece, skin_reach, skin_vertex_map
from hitogata.geometry.shells import smoothing_operator
from hitogata.fem.elements import element_order, shape_values, tet_geometry
from hitogata.options import Skinning
from hitogata.posing.skinning import Skin, prepare_skin, skin_vertices
from hitogata.volume.region_surfaces import body_region_surfaces
from hitogata.volume.surface import SurfaceIndex

if TYPE_CHECKING:
    from hitogata.dynamics.motion import BodyDynamics, Motion

# How a vertex is bound: in a tet of the mesh; deep in the body outside it (the nearest tissue); near the
# skin outside it (the nearest skin vertices' binding)
CARRIERS = ("mesh", "deep", "skin")
BLEND_STEPS = 8  # averaging steps over the surface's edges (module note)
DEEP = 2.0  # a point this many times the skin's reach (`elastic.mapping.skin_reach`) under the skin is deep


@dataclass(frozen=True, eq=False)
class CarriedSurface:
    """A surface (rest vertices (V, 3), faces (F, 3)) bound to a body's elastic model and skeleton."""

    name: str
    faces: np.ndarray
    skin: Skin  # rest = the surface's vertices, weights = the blended part weights (module note)
    method: Skinning
    elastic_map: sp.csr_matrix  # (V, N): the nodes' elastic displacement at the vertices
    carried_by: np.ndarray  # (V,) index into CARRIERS: how each vertex was bound, before the blend

    @property
    def rest(self) -> np.ndarray:
        return self.skin.rest

    def posed(self, rotations: np.ndarray, translations: np.ndarray, elastic: np.ndarray) -> np.ndarray:
        """(V, 3) the vertices for one frame: the parts' rotations (parts, 3, 3) and translations
        (parts, 3), the nodes' elastic displacement (N, 3)."""
        plain = skin_vertices(self.skin, rotations[None], translations[None], self.method)[0]
        return plain + self.elastic_map @ np.asarray(elastic, dtype=np.float64)

    def frame(self, motion: Motion, k: int) -> np.ndarray:
        """(V, 3) the vertices at a motion's frame k."""
        return self.posed(motion.rotations[k], motion.translations[k], motion.elastic[k])


def carry_surface(dynamics: BodyDynamics, name: str, vertices: np.ndarray, faces: np.ndarray) -> CarriedSurface:
    """A surface inside the dynamics' body bound to its model and skeleton (module note)."""
    from hitogata.dynamics.motion import cut_fade

    poser, model = dynamics.poser, dynamics.model
    vertices = np.asarray(vertices, dtype=np.float64)
    near, idw = nearest_skin(poser, vertices)
    n_skin = len(poser.body.vertices)
    nearest = sp.csr_matrix((idw.ravel(), (np.repeat(np.arange(len(vertices)), near.shape[1]), near.ravel())),
                            shape=(len(vertices), n_skin))
    near_skin = nearest @ poser.skin.weights
    volume = model.volume
    reach = skin_reach(volume.quality.surface_distance_max, volume.element_size)
    # inside a tet of the body's piece: that tet's
    within = _inside_map(vertices, model.points, model.elements)
    held = np.asarray(within.sum(axis=1)).ravel() > 0.5
    off = np.flatnonzero(~held)
    depth = SurfaceIndex(poser.body.vertices, poser.body.faces).distance(vertices[off])
    # deep in the body (in a held bone's hole, a gap the mesh's repair left): the nearest tissue's, whatever
    # the nearest skin moves with (deep in the chest that may be the armpit's skin, weighted to the arm)
    deep = off[depth >= DEEP * reach]
    bound = sp.diags(held.astype(np.float64)) @ within
    if len(deep):
        bound += _rows(len(vertices), deep, skin_vertex_map(vertices[deep], model.points, model.elements, reach,
                                                            DEFAULT_FADE))
    # near the skin: the nearest skin vertices' own (`NodeRig.skin_map`: only tissue that moves with them,
    # faded out beyond the mesh)
    skin_side = off[depth < DEEP * reach]
    bound += _rows(len(vertices), skin_side, nearest[skin_side] @ dynamics.rig.skin_map)
    share = np.asarray(bound.sum(axis=1)).ravel()
    weights = sp.csr_matrix(bound @ dynamics.rig.weights + sp.diags(1.0 - share) @ near_skin)
    elastic_map = sp.csr_matrix(sp.diags(cut_fade(vertices, model)) @ bound)  # as the skin beyond a trunk's cuts
    # where the carriers meet (the mesh's edge, a joint's bone nodes), each vertex's binding is blended with
    # its neighbours' over a few mm, so the surface stretches there instead of tearing
    blend = sp.identity(len(vertices), format="csr") + 0.5 * smoothing_operator(len(vertices), faces)
    for _ in range(BLEND_STEPS):
        weights, elastic_map = blend @ weights, blend @ elastic_map
    carried_by = np.zeros(len(vertices), dtype=np.int8)
    carried_by[deep], carried_by[skin_side] = CARRIERS.index("deep"), CARRIERS.index("skin")
    return CarriedSurface(name, np.asarray(faces), prepare_skin(vertices, weights, poser.skeleton.parents),
                          dynamics.rig.method, elastic_map, carried_by)


def _inside_map(points: np.ndarray, nodes: np.ndarray, elements: np.ndarray) -> sp.csr_matrix:
    """(P, N) the shape functions, at each point, of the tet of the body's piece holding it (libigl's
    AABB tree); an empty row for a point in none."""
    piece = np.flatnonzero(body_piece(elements))
    corners = np.ascontiguousarray(elements[piece, :4], dtype=np.int64)
    tree = igl.AABB()
    tree.init(nodes, corners)
    found = igl.in_element(nodes, corners, points, tree)
    rows = np.flatnonzero(found >= 0)
    tets = elements[piece[found[rows]]]
    grads, _ = tet_geometry(nodes, tets)
    bary = np.einsum("tij,tj->ti", grads, points[rows] - nodes[tets[:, 0]])
    bary[:, 0] += 1.0
    values = shape_values(element_order(elements), np.clip(bary, 0.0, 1.0))
    return sp.csr_matrix((values.ravel(), (np.repeat(rows, elements.shape[1]), tets.ravel())),
                         shape=(len(points), len(nodes)))


def _rows(n: int, rows: np.ndarray, matrix: sp.spmatrix) -> sp.csr_matrix:
    """(n, columns) the rows of `matrix` placed at `rows`, the others empty."""
    spread = sp.csr_matrix((np.ones(len(rows)), (rows, np.arange(len(rows)))), shape=(n, len(rows)))
    return sp.csr_matrix(spread @ matrix)


def carried_region_surfaces(dynamics: BodyDynamics, light: bool = False) -> tuple[CarriedSurface, ...]:
    """The whole body's tissue regions (`volume.region_surfaces.body_region_surfaces`, light or not), each
    carried by the dynamics' model and skeleton; the empty ones left out."""
    return tuple(carry_surface(dynamics, s.name, s.vertices, s.faces)
                 for s in body_region_surfaces(dynamics.poser.body, light) if len(s.faces))
