"""Where the skin passes into another part of the body: vertex–surface penetrations of a posed skin.

The skin is split into contact groups (upper arm, forearm, thigh, chest, …:
`hitogata.skin.contact.GROUPS`); a group never meets itself
(its parts are held in shape by one or two bones), so a skin vertex is
tested against the surface of every other group whose box it is near. The
query is libigl's signed distance (an AABB tree over the group's triangles,
the sign by the angle-weighted pseudonormal: Bærentzen & Aanæs 2005), built
anew for each posture.

A group's surface is open where it meets its neighbours, and neighbours
lie side by side at rest, so a vertex inside another group's surface is a
penetration only if

- its closest point is not on that surface's rim (the seam with the next
  group, where the sign says nothing), and
- at rest it lay further than `PenetrationSettings.rest_apart` from that triangle: skin
  across a seam (the two sides of a joint's own crease line) is one sheet,
  not two bodies meeting, and
- it lies in the body's tissue: the generalized winding number of the whole
  skin at the vertex (Jacobson, Kavan & Sorkine-Hornung 2013; libigl's fast
  winding number, Barill et al. 2018) is above `PenetrationSettings.covered`. The skin is closed
  (the body's is), so the winding number counts how often the body covers a
  point; at a vertex its own triangles add nothing (it lies on their planes)
  and the rest of its sheet adds the share of a small sphere round it on the
  tissue's side, below 1 (½ where the skin is smooth, more in a crease), so
  a vertex of skin that crosses nothing reads below 1 (its tissue's cone at
  the vertex is less than the whole sphere) and one inside another part 1
  more. The open surface of one group cannot tell its inside from a
  crease's gap: skin tucked into the groin under another group's open rim
  (male hip flexion 120° with contact, no triangle pair crossing) lies
  "inside" it by the signed distance, but reads 0.62–0.98, outside the body
  between two sheets of skin; so do a few vertices in the creases of the
  poses without contact (0.43–0.55: male hip flexion, female knee). The
  true penetrations of hip flexion, hip adduction, elbow and knee, skinned
  and elastic, read 1.09 and more (1.23 and more but one vertex in the
  female elbow's crease).

The same test on the rest skin finds the rest body's own contacts (the
thighs of a heavy body, an arm against the side); a vertex inside a group at
rest is never reported inside that group: a pose is judged on what it adds.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np
import scipy.sparse as sp

from hitogata.errors import require_above
from hitogata.geometry.mesh_checks import winding_number
from hitogata.geometry.closest import barycentric_on_triangles, closest_points_on_triangles

_RIM = 1e-6  # barycentric weight under which a closest point lies on a triangle's edge (round-off, not a choice)


@dataclass(frozen=True)
class PenetrationSettings:
    """What the test counts as skin inside another part, SI (m). Refused when out of range (`__post_init__`)."""

    detect: float = 0.025
    """m: the deepest penetration looked for; deeper, the closest surface is often the wrong one (a calf 6 cm
    into the thigh at a 135° knee is closer to the thigh's side than to its back)."""
    rest_apart: float = 0.02
    """m: a vertex and a triangle this close at rest are one sheet of skin, never in contact."""
    covered: float = 1.01
    """winding number above which a skin vertex lies inside another part (module note): 1, plus a margin over
    the fast evaluation's error (at most 0.004 against the exact winding number, measured)."""

    def __post_init__(self) -> None:
        require_above("PenetrationSettings.detect", self.detect, what="a distance (m)")
        require_above("PenetrationSettings.rest_apart", self.rest_apart, what="a distance (m)")
        require_above("PenetrationSettings.covered", self.covered, 0.5, "a winding number")  # ½: a smooth sheet's own


PENETRATION_DEFAULTS = PenetrationSettings()


@dataclass(frozen=True)
class Penetrations:
    """Skin vertices inside another group's surface: the vertex, the triangle it is closest to,
    the barycentric weights of that closest point, the surface's outward unit normal there, and
    the depth (m, > 0)."""

    vertex: np.ndarray  # (K,)
    face: np.ndarray  # (K,)
    barycentric: np.ndarray  # (K, 3)
    normal: np.ndarray  # (K, 3)
    depth: np.ndarray  # (K,)

    def __len__(self) -> int:
        return len(self.vertex)

    @property
    def deepest(self) -> float:
        """The largest depth (m), 0 with no penetration."""
        return float(self.depth.max(initial=0.0))

    def subset(self, keep: np.ndarray) -> Penetrations:
        """The penetrations selected by `keep` (a mask or indices)."""
        return Penetrations(*(getattr(self, f.name)[keep] for f in fields(self)))


class SelfContact:
    """The contact test of one skin (rest vertices, faces, a group per vertex), for any posture of it, counting
    penetrations as `settings` say."""

    def __init__(self, rest: np.ndarray, faces: np.ndarray, groups: np.ndarray,
                 settings: PenetrationSettings = PENETRATION_DEFAULTS) -> None:
        self.settings = settings
        self.rest = np.asarray(rest, dtype=float)
        self.faces = np.asarray(faces, dtype=np.int64)
        self.groups = np.asarray(groups)
        self.n_groups = int(self.groups.max(initial=-1)) + 1
        face_group = self.groups[self.faces]
        # a triangle belongs to a group when all its corners do; seam triangles to none
        whole = (face_group == face_group[:, :1]).all(axis=1)
        self._group_faces = [np.flatnonzero(whole & (face_group[:, 0] == g)) for g in range(self.n_groups)]
        self._rim = [self._rim_vertices(f) for f in self._group_faces]
        self._at_rest = self._search(self.rest, rest_check=False)
        edges = np.concatenate([self.faces[:, [0, 1]], self.faces[:, [1, 2]], self.faces[:, [2, 0]]])
        adjacency = sp.coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(len(rest),) * 2)
        adjacency = ((adjacency + adjacency.T) > 0).astype(float)
        degree = np.asarray(adjacency.sum(axis=1)).ravel()
        self.neighbour_average = (sp.diags(1.0 / np.maximum(degree, 1.0)) @ adjacency).tocsr()

    def _rim_vertices(self, faces: np.ndarray) -> np.ndarray:
        """(V,) bool: vertices on the open boundary of the group's surface."""
        tri = self.faces[faces]
        edges = np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
        keys, counts = np.unique(edges[:, 0] * len(self.rest) + edges[:, 1], return_counts=True)
        rim = np.zeros(len(self.rest), dtype=bool)
        open_edges = keys[counts == 1]
        rim[open_edges // len(self.rest)] = True
        rim[open_edges % len(self.rest)] = True
        return rim

    def penetrations(self, vertices: np.ndarray) -> Penetrations:
        """The posture's penetrations beyond the rest body's own (vertices (V, 3), m)."""
        found = self._search(np.asarray(vertices, dtype=float), rest_check=True)
        key = found.vertex * self.n_groups + self.groups[self.faces[found.face, 0]]
        rest_key = self._at_rest.vertex * self.n_groups + self.groups[self.faces[self._at_rest.face, 0]]
        return found.subset(~np.isin(key, rest_key))

    def _query(self, x: np.ndarray, group: int, points: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Signed distance (> 0 outside) of skin vertices `points` to group's surface at x, within
        ±`settings.detect`: the closest triangle, its barycentric weights, the outward unit normal there, and
        whether the closest point is off the surface's rim."""
        import igl

        detect = self.settings.detect
        faces = self._group_faces[group]
        signed, which, closest, normal = igl.signed_distance(
            x[points], x, self.faces[faces], igl.SIGNED_DISTANCE_TYPE_PSEUDONORMAL, -detect, detect)
        found = (which >= 0) & (which < len(faces))  # points beyond the bound get no triangle
        which = np.where(found, which, 0)
        signed = np.where(found, signed, detect)
        normal = np.where(found[:, None], normal, 0.0)  # libigl leaves those unset
        face = faces[which]
        corners = self.faces[face]
        bary = barycentric_on_triangles(closest, x[corners])
        rim = self._rim[group][corners]
        on_rim = (rim & (bary > 1.0 - _RIM)).any(axis=1)  # at a rim vertex
        edge_on_rim = rim & np.roll(rim, -1, axis=1)  # edge (a, a+1) has both ends on the rim
        on_rim |= (edge_on_rim & (np.roll(bary, 1, axis=1) <= _RIM)).any(axis=1)  # on that edge
        norms = np.linalg.norm(normal, axis=1, keepdims=True)
        return signed, face, bary, normal / np.maximum(norms, 1e-30), found & ~on_rim

    def _search(self, x: np.ndarray, rest_check: bool) -> Penetrations:
        lo_all, hi_all = x.min(axis=0), x.max(axis=0)
        out: list[tuple[np.ndarray, ...]] = []
        detect = self.settings.detect
        for g, faces in enumerate(self._group_faces):
            if not len(faces):
                continue
            tri = x[self.faces[faces]]
            lo, hi = tri.min(axis=(0, 1)) - detect, tri.max(axis=(0, 1)) + detect
            if np.any(hi < lo_all) or np.any(lo > hi_all):
                continue
            near = np.flatnonzero((self.groups != g) & np.all((x >= lo) & (x <= hi), axis=1))
            if not len(near):
                continue
            signed, face, bary, normal, off_rim = self._query(x, g, near)
            keep = (signed < 0.0) & off_rim
            if rest_check:
                keep[keep] = _point_triangle_distance(self.rest[near[keep]], self.rest[self.faces[face[keep]]]) \
                    > self.settings.rest_apart
            out.append((near[keep], face[keep], bary[keep], normal[keep], -signed[keep]))
        if not out:
            out.append((np.zeros(0, int), np.zeros(0, int), np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0)))
        vertex, face, bary, normal, depth = (np.concatenate(parts) for parts in zip(*out))
        keep = self._in_tissue(x, vertex)
        vertex, face, bary, normal, depth = vertex[keep], face[keep], bary[keep], normal[keep], depth[keep]
        # a vertex inside two groups (the armpit: arm and chest) keeps its deeper one
        order = np.lexsort((-depth, vertex))
        first = order[np.diff(vertex[order], prepend=-1) != 0]
        return Penetrations(vertex[first], face[first], bary[first], normal[first], depth[first])


    def _in_tissue(self, x: np.ndarray, vertices: np.ndarray) -> np.ndarray:
        """(K,) bool: the skin at x covers each vertex more than its own sheet does (winding number
        above `settings.covered`): inside another part, not tucked into a gap between two sheets of skin."""
        if not len(vertices):
            return np.zeros(0, dtype=bool)
        return np.abs(winding_number(x, self.faces, x[vertices], fast=True)) > self.settings.covered


def _point_triangle_distance(points: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """(K,) distance of each point to its triangle (K, 3, 3)."""
    closest = closest_points_on_triangles(points, tri[:, 0], tri[:, 1], tri[:, 2])
    return np.linalg.norm(points - closest, axis=1)

