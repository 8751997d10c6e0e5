"""The skin's self-contact as a barrier problem (IPC: Li et al. 2020, Incremental Potential Contact).

A study beside `hitogata.geometry.contact.separate` (which parts the skin vertex by vertex): here the
skin near contact is the unknown of one smooth minimisation,

    E(x) = ½ (x − y)ᵀ (I + k·L) (x − y) + κ Σ b(d(x)),

where y is the posture's skin (elastic or skinned), L the skin's uniform graph Laplacian (a pushed
region carries its neighbours with it, as a membrane would), and b the IPC log barrier (`dhat`) over the
vertex–face and edge–edge distances between different contact groups (`hitogata.dynamics.contact`:
never within a group, never a vertex pair that lay within `REST_APART` at rest, i.e. across a seam or
touching at rest). The barrier is infinite at contact, so a start free of crossings stays free if every
Newton step is cut short by continuous collision detection: the pose is reached along a path (rest →
intermediate postures → the target), each step's minimum found from the last one.

The collision queries, distances, barrier derivatives and CCD are the IPC Toolkit's (`ipctk`, MIT).
Only the neighbourhood of the contacts is free (`REACH` of another group in the target, grown by
`RINGS` rings); the rest of the skin follows its target.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.spatial import cKDTree

from hitogata.geometry.contact import REST_APART, SelfContact
from hitogata.volume.surface import closest_points_on_triangles

DHAT = 2e-3  # m: the barrier's reach; skin in contact ends up within it
APART = 2 * DHAT  # m: primitives nearer than this at rest never collide (they would start inside the barrier)
STIFFNESS = 1e8  # barrier weight against the tracking energy (the toolkit's barrier is of squared distances, ~1e-8 at 1 mm)
SMOOTHING = 10.0  # k: the Laplacian's weight; a push spreads over ~√k rings
REACH = 0.03  # m: a vertex this close to another group's vertex in the target may meet it
RINGS = 3  # rings of skin around those that are free to move
NEWTON = 30  # most Newton iterations a step
# m⁻⁴: weight of ½ (V − V_target)², the enclosed volume held to the target's (whose overlaps count twice:
# the tissue a contact presses aside comes back as a swelling of the free skin around it)
INCOMPRESSIBILITY = 1e9
TOLERANCE = 5e-4  # m: a Newton step below this (largest vertex move) has converged
# m: CCD keeps the skin this far apart along a step (its time-of-impact tolerance is relative to the
# step, so a long step could otherwise end nanometres from contact, where the next CCD misses a crossing)
CCD_GAP = 0.005 * DHAT
MAX_STEP = 0.02  # m: the longest vertex move of one Newton step (a trust region: CCD then sees contact coming)


@dataclass(frozen=True)
class BarrierResult:
    """The resolved skin (V, 3), the free vertices, Newton iterations taken per path step, and the
    smallest distance (m) between skin that may collide at the end."""

    vertices: np.ndarray
    free: np.ndarray
    iterations: list[int]
    min_distance: float


def _adjacency(faces: np.ndarray, n: int) -> sp.csr_matrix:
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    a = sp.coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
    return ((a + a.T) > 0).astype(float).tocsr()


def _grow(mask: np.ndarray, adjacency: sp.csr_matrix, rings: int) -> np.ndarray:
    out = mask.copy()
    for _ in range(rings):
        out = out | (adjacency @ out.astype(float) > 0)
    return out


def contact_region(target: np.ndarray, test: SelfContact, adjacency: sp.csr_matrix,
                   reach: float = REACH, rings: int = RINGS) -> np.ndarray:
    """(V,) bool: skin that may meet another group in `target` (a vertex within `reach` of another
    group's vertex that lay at least `reach` further away at rest: contacts the posture brings, not
    the rest body's own), grown by `rings`."""
    pairs = cKDTree(target).query_pairs(reach, output_type="ndarray")
    i, j = pairs[:, 0], pairs[:, 1]
    keep = test.groups[i] != test.groups[j]
    i, j = i[keep], j[keep]
    now = np.linalg.norm(target[i] - target[j], axis=1)
    keep = np.linalg.norm(test.rest[i] - test.rest[j], axis=1) > now + reach
    near = np.zeros(len(target), dtype=bool)
    near[i[keep]] = True
    near[j[keep]] = True
    return _grow(near, adjacency, rings)


class _Problem:
    """The barrier problem on the sub-mesh around the contacts: the collision mesh, which of its
    primitive pairs may collide, the tracking energy's matrix restricted to the free vertices."""

    def __init__(self, test: SelfContact, free: np.ndarray, adjacency: sp.csr_matrix, stiffness: float,
                 smoothing: float, dhat: float, incompressibility: float) -> None:
        import ipctk

        self.incompressibility = incompressibility

        # the collision mesh: the free skin's triangles; every vertex of it is an unknown (a fixed
        # vertex would jump with its target, unchecked by CCD)
        faces = test.faces[free[test.faces].all(axis=1)]
        self.vertices = np.unique(faces)  # global ids of the sub-mesh's vertices
        local = np.full(len(test.rest), -1)
        local[self.vertices] = np.arange(len(self.vertices))
        self.faces = local[faces].astype(np.int32)
        # the triangles whose volume the unknowns change: those with a corner in the sub-mesh
        self.touching = test.faces[(local[test.faces] >= 0).any(axis=1)]
        self.local = local
        self.free = free[self.vertices]  # (n,) bool, sub-mesh order
        self.rest = test.rest[self.vertices]
        self.edges = np.asarray(ipctk.edges(self.faces), dtype=np.int32)
        self.mesh = ipctk.CollisionMesh(self.rest, self.edges, self.faces)
        self.groups = test.groups[self.vertices].astype(np.int32)
        # the toolkit's filter passes a triangle–vertex pair when ANY corner may meet the vertex; it
        # prunes the broad phase (different groups), `_allowed` then asks it of every corner
        self.mesh.can_collide = ipctk.make_vertex_patches_filter(self.groups)
        self.dhat = dhat
        self.barrier = ipctk.BarrierPotential(dhat, stiffness)
        n = len(self.vertices)
        sub = adjacency[self.vertices][:, self.vertices]
        laplacian = sp.diags(np.asarray(sub.sum(axis=1)).ravel()) - sub
        a = (sp.identity(n) + smoothing * laplacian).tocsr()
        self.tracking = sp.kron(a, sp.identity(3)).tocsr()  # dofs vertex-major (x0, y0, z0, x1, …)
        self.dofs = np.flatnonzero(np.repeat(self.free, 3))
        self.tracking_ff = self.tracking[self.dofs][:, self.dofs].tocsc()

    def candidates(self, x0: np.ndarray, x1: np.ndarray):  # type: ignore[no-untyped-def]
        """The primitive pairs that may come within dhat of each other on the way x0 → x1, those of
        different groups that lay more than REST_APART apart at rest."""
        import ipctk

        c = ipctk.Candidates()
        c.build(self.mesh, x0, x1, self.dhat)
        fv = np.array([(k.face_id, k.vertex_id) for k in c.fv_candidates], dtype=np.int64).reshape(-1, 2)
        ee = np.array([(k.edge0_id, k.edge1_id) for k in c.ee_candidates], dtype=np.int64).reshape(-1, 2)
        keep_fv, keep_ee = self._allowed_fv(fv), self._allowed_ee(ee)
        c.fv_candidates = [ipctk.FaceVertexCandidate(int(f), int(v)) for f, v in fv[keep_fv]]
        c.ee_candidates = [ipctk.EdgeEdgeCandidate(int(a), int(b)) for a, b in ee[keep_ee]]
        return c

    def _allowed_fv(self, fv: np.ndarray) -> np.ndarray:
        corners = self.faces[fv[:, 0]]
        other = (self.groups[corners] != self.groups[fv[:, 1], None]).any(axis=1)
        tri = self.rest[corners]
        closest = closest_points_on_triangles(self.rest[fv[:, 1]], tri[:, 0], tri[:, 1], tri[:, 2])
        return other & (np.linalg.norm(self.rest[fv[:, 1]] - closest, axis=1) > APART)

    def _allowed_ee(self, ee: np.ndarray) -> np.ndarray:
        a, b = self.edges[ee[:, 0]], self.edges[ee[:, 1]]
        ga, gb = self.groups[a], self.groups[b]
        other = (ga[:, :, None] != gb[:, None, :]).any(axis=(1, 2))
        r = self.rest
        apart = np.minimum.reduce([_point_segment(r[a[:, 0]], r[b[:, 0]], r[b[:, 1]]),
                                   _point_segment(r[a[:, 1]], r[b[:, 0]], r[b[:, 1]]),
                                   _point_segment(r[b[:, 0]], r[a[:, 0]], r[a[:, 1]]),
                                   _point_segment(r[b[:, 1]], r[a[:, 0]], r[a[:, 1]])])
        return other & (apart > APART)

    def collisions(self, candidates, x: np.ndarray):  # type: ignore[no-untyped-def]
        import ipctk

        c = ipctk.NormalCollisions()
        c.build(candidates, self.mesh, x, self.dhat)
        return c

    def volume(self, x: np.ndarray, target: np.ndarray) -> tuple[float, np.ndarray]:
        """The enclosed volume's change (m³) from `target` (the whole skin, V×3) with the sub-mesh at
        x, and its gradient (n, 3) in x."""
        full = target[self.touching]  # (T, 3, 3)
        moved = full.copy()
        inside = self.local[self.touching]
        moved[inside >= 0] = x[inside[inside >= 0]]
        change = (np.einsum("ij,ij->i", moved[:, 0], np.cross(moved[:, 1], moved[:, 2]))
                  - np.einsum("ij,ij->i", full[:, 0], np.cross(full[:, 1], full[:, 2]))).sum() / 6.0
        gradient = np.zeros_like(x)
        for k in range(3):
            part = np.cross(moved[:, (k + 1) % 3], moved[:, (k + 2) % 3]) / 6.0
            keep = inside[:, k] >= 0
            np.add.at(gradient, inside[keep, k], part[keep])
        return float(change), gradient

    def energy(self, candidates, x: np.ndarray, y: np.ndarray, target: np.ndarray) -> float:  # type: ignore[no-untyped-def]
        d = (x - y).ravel()
        change, _ = self.volume(x, target)
        return (0.5 * float(d @ (self.tracking @ d)) + 0.5 * self.incompressibility * change ** 2
                + self.barrier(self.collisions(candidates, x), self.mesh, x))

    def minimise(self, x: np.ndarray, target: np.ndarray, iterations: int, tolerance: float
                 ) -> tuple[np.ndarray, int]:
        """Newton from x (free of crossings) towards the minimum for the whole skin's `target`, every
        step limited by CCD and backtracked to decrease the energy (the volume term Gauss–Newton, its
        rank-one Hessian by Sherman–Morrison)."""
        import ipctk

        x = x.copy()
        y = target[self.vertices]
        near = self.candidates(x, x)
        taken = 0
        for taken in range(1, iterations + 1):
            c = self.collisions(near, x)
            d = (x - y).ravel()
            change, w = self.volume(x, target)
            w = w.ravel()[self.dofs]
            gradient = (self.tracking @ d + self.barrier.gradient(c, self.mesh, x))[self.dofs] \
                + self.incompressibility * change * w
            hessian = self.barrier.hessian(c, self.mesh, x, ipctk.PSDProjectionMethod.CLAMP)
            h = spla.splu((self.tracking_ff + hessian.tocsr()[self.dofs][:, self.dofs]).tocsc())
            u, v = h.solve(-gradient), h.solve(w)
            step = np.zeros(x.size)
            step[self.dofs] = u - v * (self.incompressibility * (w @ u) / (1.0 + self.incompressibility * (w @ v)))
            step = step.reshape(-1, 3)
            longest = float(np.linalg.norm(step, axis=1).max())
            if longest < tolerance:
                break
            step *= min(1.0, MAX_STEP / longest)
            swept = self.candidates(x, x + step)
            alpha = min(1.0, swept.compute_collision_free_stepsize(self.mesh, x, x + step, CCD_GAP))
            e0 = self.energy(near, x, y, target)
            slope = float(gradient @ step.ravel()[self.dofs])
            while alpha > 1e-6 and self.energy(swept, x + alpha * step, y, target) > e0 + 1e-4 * alpha * slope:
                alpha *= 0.5
            x = x + alpha * step
            near = swept
            if alpha * np.abs(step).max() < tolerance:
                break
        return x, taken

    def min_distance(self, x: np.ndarray) -> float:
        c = self.collisions(self.candidates(x, x), x)
        return float(np.sqrt(c.compute_minimum_distance(self.mesh, x))) if len(c) else self.dhat


def _point_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(K,) distance of each point to its segment a→b (all (K, 3))."""
    d = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-30), 0.0, 1.0)
    return np.linalg.norm(p - a - t[:, None] * d, axis=1)


def barrier_resolve(path: Sequence[np.ndarray], test: SelfContact, stiffness: float = STIFFNESS,
                    smoothing: float = SMOOTHING, dhat: float = DHAT, reach: float = REACH, rings: int = RINGS,
                    iterations: int = NEWTON, tolerance: float = TOLERANCE,
                    incompressibility: float = INCOMPRESSIBILITY) -> BarrierResult:
    """The skin at the last of `path`'s postures (each (V, 3); the first should be free of crossings,
    e.g. the rest skin), with no skin of one contact group passing into another's: each posture in
    turn is the target y of the barrier problem, started from the previous solution."""
    adjacency = _adjacency(test.faces, len(test.rest))
    target = np.asarray(path[-1], dtype=float)
    free = contact_region(target, test, adjacency, reach, rings)
    problem = _Problem(test, free, adjacency, stiffness, smoothing, dhat, incompressibility)
    ids = problem.vertices
    x = np.array(path[0], dtype=float)[ids]
    taken = []
    for y in path[1:]:
        x, n = problem.minimise(x, np.asarray(y, dtype=float), iterations, tolerance)
        taken.append(n)
    out = target.copy()
    out[ids] = x
    return BarrierResult(out, free, taken, problem.min_distance(x))
