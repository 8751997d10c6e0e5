"""The skin sliding over the fascia: stretch beyond what skin takes spread to the skin around it.

Skinning and the elastic body stretch the skin where a joint opens (the armpit overhead, the groin and
the buttock at hip flexion, the elbow's point) into bands of triangles stretched two to fifteen times,
where real skin slides over the fascia and spreads the stretch over a wide area, tethered to the fascia
by its fibrous septa (so the slide dies away from the opening joint). Here the posed coarse skin's
vertices near such bands slide within the posed surface, the shape unchanged, until the fine skin
(`hitogata.skin.fine_skin`, carried by the coarse skin through its Loop stencils) is stretched no
more than `SlideSettings.done` along any direction nor in area (the constants: `skin.settings.SlideSettings`).

The slid skin x minimises, over the free coarse vertices and on the posed surface,

    E(x) = Σ_f A_f (s ‖F_f − T_f‖² + h_f ‖F_f − L_f‖²) + Σ_i τ a_i ‖x_i − x⁰_i‖²,

F_f a triangle's deformation gradient from rest (rest area A_f; the fine triangles the free vertices
carry and the coarse triangles themselves), T_f its nearest gradient with no principal stretch above 1
(a tension-field membrane: skin resists stretch, not compression, which it takes in wrinkles; weight
`tension`), L_f its nearest gradient with principal stretches and area ratio at most `limit` (weight
h_f = 1 once the triangle has been beyond it, else 0); both keep the smaller principal stretch at least
`floor` (or what it was, if less: a crease's skin stays as short) and the triangle's side up. The
tether (the fascia) holds each vertex (rest area a_i) to where the contact left it, x⁰, with a stiffness
τ = s / `falloff`²: a slide dies away over about `falloff` from where the skin is pulled. It is solved by
local/global steps (the projections as in projective dynamics, Bouaziz et al. 2014, *Projective
Dynamics*, ACM TOG 33(4)): the local step projects every triangle (an SVD each, in closed form), the
global one solves the energy's quadratic model for the free vertices' moves along their tangent planes
(two unknowns a vertex, a sparse solve), then the vertices go back to the posed surface near where they
lay (never across a crease) and a move that would turn a coarse triangle over (`SlideLevel.tilts`) or
shrink it away (`SlideLevel.shrink`) is left out there.

Free: the coarse skin within `reach` (along the skin's edges) of the fine skin beyond `done`. If the
slid skin crosses itself where it did not (a slide across the bottom of a tight crease carries the
skin's chords through its other side), it slides again with less turning allowed, then with the skin
there held (the fine skin's first tied harder to where it lay, then held), and what still crosses has its
slide undone. Holding lets the skin round it slide again to meet it; putting it back alone tears it from
its slid neighbours, which then cross in their turn (the large man's groin: 22 → 91 → 538 → … → 0
pairs, docs/decisions/0062-a-held-posture-by-chebyshev-steps.md).

Where the coarse triangles may turn no further (over the armpit's hollow overhead, the groin's sharp
folds), fine skin stays beyond `done`. The fine skin then slides on its own (`slide_fine_skin`): the same
energy and steps with its own vertices free on its own posed surface (`SlideSettings.fine`: a fine triangle turns at
most 90° from the surface's smooth normal under it, and the slide dies away within 2 cm). The slid fine
skin is what is measured; it no longer follows the coarse skin through the Loop stencils
(`ElasticPose.fine_vertices`, and its own file beside `hitogata pose`'s).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import dijkstra

from hitogata.fem.factor import SamePatternSolves
from hitogata.geometry.mesh_checks import edge_graph, self_intersections
from hitogata.geometry.normals import triangle_normals, vertex_areas, vertex_normals
from hitogata.skin.fine_skin import FineSkinning
from hitogata.geometry.strain import RestFrames, principal_stretches
from hitogata.options import Skinning
from hitogata.skeleton.kinematics import Pose
from hitogata.skin.settings import SKIN_DEFAULTS, SkinSettings, SlideLevel, SlideSettings
from hitogata.geometry.closest import barycentric_on_triangles, closest_points_on_triangles, nearest_in_groups



@dataclass(frozen=True)
class SlideResult:
    """A slid skin (the coarse or the fine one) (V, 3), how far each vertex slid (V,) m, the free vertices
    (V,) bool, and the local/global steps taken."""

    vertices: np.ndarray
    moved: np.ndarray
    free: np.ndarray
    iterations: int


@dataclass(frozen=True)
class SkinSlide:
    """A posed skin's slide: the coarse skin's within its surface, then the fine skin's own (its
    vertices: the slid fine skin, what is measured)."""

    coarse: SlideResult
    fine: SlideResult


@dataclass(frozen=True)
class _Carried:
    """The fine skin a sliding coarse skin carries: posed (Vf, 3), at rest, its faces, its stencils."""

    vertices: np.ndarray
    rest: np.ndarray
    faces: np.ndarray
    interpolation: sp.csr_matrix


def _over(rest: np.ndarray, deformed: np.ndarray, faces: np.ndarray, limit: float, frames: RestFrames | None = None
          ) -> np.ndarray:
    """(F,) bool: the triangles stretched, or grown in area, beyond `limit` (frames: the rest's, if found before)."""
    stretch_max, _, area_ratio, _, _ = principal_stretches(rest, deformed, faces, frames)
    return (stretch_max > limit) | (area_ratio > limit)


def _gradient_operator(rest: np.ndarray, faces: np.ndarray) -> tuple[sp.csr_matrix, np.ndarray]:
    """(2F, Vf) G with (G @ X)[2f + j] = column j of triangle f's deformation gradient (in its rest plane
    frame) for vertex positions X (Vf, 3); and the rest areas (F,)."""
    tri = rest[faces]
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    length = np.linalg.norm(e1, axis=1)
    t = e1 / length[:, None]
    normal = np.cross(e1, e2)
    area = 0.5 * np.linalg.norm(normal, axis=1)
    b = np.cross(normal, e1)
    b /= np.linalg.norm(b, axis=1)[:, None]
    d = np.zeros((len(faces), 2, 2))  # rest edges in the frame (t, b), as columns
    d[:, 0, 0] = length
    d[:, 0, 1] = np.einsum("ij,ij->i", e2, t)
    d[:, 1, 1] = np.einsum("ij,ij->i", e2, b)
    m = np.linalg.inv(d)  # F = [e1 e2] m: rows m[0], m[1] weigh e1 and e2
    coef = np.stack([-(m[:, 0] + m[:, 1]), m[:, 0], m[:, 1]], axis=1)  # (F, 3 corners, 2 columns)
    rows = (2 * np.arange(len(faces)))[:, None, None] + np.arange(2)[None, None, :]
    rows = np.broadcast_to(rows, coef.shape)
    cols = np.broadcast_to(faces[:, :, None], coef.shape)
    g = sp.csr_matrix((coef.ravel(), (rows.ravel(), cols.ravel())), shape=(2 * len(faces), len(rest)))
    return g, area


def _svd(f: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The thin SVD of (F, 3, 2) gradients, u (F, 3, 2), s (F, 2) descending, vt (F, 2, 2), in closed
    form from the eigenpairs of the 2 × 2 FᵀF (numpy's batched SVD takes ten times as long)."""
    c = np.einsum("fki,fkj->fij", f, f)
    half_trace, half_gap = 0.5 * (c[:, 0, 0] + c[:, 1, 1]), 0.5 * (c[:, 0, 0] - c[:, 1, 1])
    radius = np.hypot(half_gap, c[:, 0, 1])
    s = np.sqrt(np.maximum(np.stack([half_trace + radius, half_trace - radius], axis=1), 0.0))
    angle = 0.5 * np.arctan2(c[:, 0, 1], half_gap)  # the larger eigenvalue's direction
    v = np.stack([np.stack([np.cos(angle), np.sin(angle)], axis=1),
                  np.stack([-np.sin(angle), np.cos(angle)], axis=1)], axis=2)  # (F, 2, 2): eigenvectors as columns
    fv = np.einsum("fij,fjk->fik", f, v)
    u = fv / np.maximum(s, 1e-300)[:, None, :]
    return u, s, v.transpose(0, 2, 1)


def _targets(f: np.ndarray, u: np.ndarray, s: np.ndarray, vt: np.ndarray, floor: np.ndarray, up: np.ndarray,
             over: np.ndarray, slide: SlideSettings) -> np.ndarray:
    """(F, 3, 2) each gradient's (f, its SVD u, s, vt) weighted target (s T + h L) / (s + h), s the slide's
    tension: T with principal stretches in [floor, 1], L in [floor, limit] with area ratio ≤ limit (h = 1
    where `over`);
    a triangle slid over onto its back is turned back (its second direction reversed, at the floor)."""
    u, s = u.copy(), s.copy()
    flipped = np.einsum("fi,fi->f", np.cross(f[:, :, 0], f[:, :, 1]), up) < 0
    u[flipped, :, 1] *= -1.0
    s[flipped, 1] = floor[flipped]
    limit, tension = slide.limit, slide.tension
    limited = np.clip(s, floor[:, None], limit)
    limited *= np.minimum(1.0, np.sqrt(limit / np.maximum(limited[:, :1] * limited[:, 1:], 1e-300)))
    hard = over.astype(float)
    weight = tension + hard
    target = (tension * np.clip(s, floor[:, None], 1.0) + hard[:, None] * limited) / weight[:, None]
    return np.einsum("fij,fj,fjk->fik", u, target, vt)


def _tangents(normals: np.ndarray) -> np.ndarray:
    """(n, 3, 2) two unit tangents per normal."""
    helper = np.where(np.abs(normals[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    u = np.cross(normals, helper)
    u /= np.linalg.norm(u, axis=1)[:, None]
    return np.stack([u, np.cross(normals, u)], axis=2)


def slide_skin(rest: np.ndarray, coarse: np.ndarray, faces: np.ndarray, fine_rest: np.ndarray, fine_faces: np.ndarray,
               interpolation: sp.csr_matrix, fine_base: np.ndarray, settings: SkinSettings = SKIN_DEFAULTS,
               fine_frames: RestFrames | None = None) -> SlideResult:
    """The coarse skin `coarse` (V, 3; `rest` at rest) slid within its surface until its fine skin
    (`fine_base + interpolation @ coarse`, rest `fine_rest`, `fine_faces`) is stretched at most
    `settings.slide.done` (principal stretch and area ratio); unchanged where none is beyond (crossings: `_slide`).
    fine_frames: the fine rest's `geometry.strain.rest_frames`, if found before."""
    slide = settings.slide
    coarse = np.asarray(coarse, dtype=float)
    carried = _Carried(fine_base + interpolation @ coarse, fine_rest, fine_faces, interpolation)
    over = _over(fine_rest, carried.vertices, fine_faces, slide.done, fine_frames)
    seeds = np.unique(np.asarray(interpolation[np.unique(fine_faces[over])].indices))
    return _slide(rest, coarse, faces, seeds, carried, slide.coarse, slide)


def slide_fine_skin(rest: np.ndarray, fine: np.ndarray, faces: np.ndarray, settings: SkinSettings = SKIN_DEFAULTS,
                    frames: RestFrames | None = None) -> SlideResult:
    """The fine skin `fine` (Vf, 3; `rest` at rest) slid within its own surface, its vertices free, until
    none of its triangles is stretched beyond `settings.slide.done`: the stretch the coarse skin's slide left
    where its own triangles may turn no further (the armpit's hollow overhead) spread over the fine triangles.
    frames: the rest's `geometry.strain.rest_frames`, if found before."""
    slide = settings.slide
    fine = np.asarray(fine, dtype=float)
    over = _over(rest, fine, faces, slide.done, frames)
    return _slide(rest, fine, faces, np.unique(faces[over]), None, slide.fine, slide)


def _slide(rest: np.ndarray, start: np.ndarray, faces: np.ndarray, seeds: np.ndarray, carried: _Carried | None,
           level: SlideLevel, slide: SlideSettings) -> SlideResult:
    """The skin `start` slid (`_relax`) as `level` and `slide` say, its vertices within `slide.reach` of `seeds`
    free. Skin whose
    sliding would cross other skin (new self-crossing pairs, `self_intersections`; where the input crossed
    itself already, more pairs than it had) is held where it is, a ring around it too, or its tether made
    `level.stiffening` times as stiff and then held, and the rest slides again (`slide.hold_rounds` times at most
    each; then the slide is undone around what still crosses)."""
    n = len(start)
    if not len(seeds):
        return SlideResult(start, np.zeros(n), np.zeros(n, dtype=bool), 0)
    graph = edge_graph(rest, faces)
    free = np.isfinite(dijkstra(graph, directed=False, indices=seeds, limit=slide.reach, min_only=True))
    ring = graph + graph.T

    def crossing(x: np.ndarray) -> np.ndarray:
        """(V,) bool: the vertices of pairs crossing in x and not in the input, and a ring around them; none
        where the input crossed itself already and x crosses no more (the slide moved which pairs cross)."""
        before, after = _crossings_near(start, x, faces)
        new = np.array(sorted(after - before), dtype=np.int64).reshape(-1, 2)
        near = np.zeros(n, dtype=bool)
        if len(new) and not (before and len(after) <= len(before)):
            near[faces[new.ravel()].ravel()] = True
            near |= ring @ near.astype(float) > 0
        return near

    tied = np.ones(n)  # each vertex's tether, times the tether's
    for rounds, tilt in enumerate((*level.tilts, *[level.tilts[-1]] * slide.hold_rounds)):
        x, steps = _relax(rest, start, faces, free, tilt, level, carried, tied, slide)
        held = crossing(x)
        if not held.any():
            return SlideResult(x, np.linalg.norm(x - start, axis=1), free, steps)
        if rounds < len(level.tilts) - 1:  # a gentler slide first, then the skin that crosses held or tied harder
            continue
        if level.stiffening is None:
            free &= ~held
        else:
            tied[held] *= level.stiffening
    if level.stiffening is not None:  # tied harder and still crossing: that skin held, the rest slid again
        for _ in range(slide.hold_rounds):
            free &= ~held
            x, steps = _relax(rest, start, faces, free, level.tilts[-1], level, carried, tied, slide)
            held = crossing(x)
            if not held.any():
                break
    while held.any():  # still crossing: the slide is undone around the crossings until none is left
        free &= ~held
        x[held] = start[held]
        held = crossing(x)
    return SlideResult(x, np.linalg.norm(x - start, axis=1), free, steps)


def _crossings_near(start: np.ndarray, x: np.ndarray, faces: np.ndarray
                    ) -> tuple[set[tuple[int, int]], set[tuple[int, int]]]:
    """The self-crossing face pairs of `start` and of `x` (both (V, 3)) that may differ between them: those
    among the faces that moved and the faces near them, where they were or are; every other pair is the
    same in both. Near: in the cells of a grid as wide as two longest edges next to a moved face's (two
    triangles that cross have centroids closer than their longest edges together)."""
    moved = (x != start).any(axis=1)[faces].any(axis=1)
    if not moved.any():
        return set(), set()
    both = np.concatenate([start[faces], x[faces]])  # (2F, 3, 3): the faces where they were, then are
    width = 2.0 * float(np.linalg.norm(both - np.roll(both, 1, axis=1), axis=2).max())
    cell = np.floor(both.mean(axis=1) / width).astype(np.int64)
    cell -= cell.min(axis=0) - 1
    shape = tuple(int(k) for k in cell.max(axis=0) + 2)
    key = np.ravel_multi_index(tuple(cell.T), shape)
    around = np.stack(np.meshgrid(*[[-1, 0, 1]] * 3, indexing="ij"), axis=-1).reshape(-1, 3)
    hot = np.unique(cell[np.concatenate([moved, moved])], axis=0)
    hot = np.unique(np.ravel_multi_index(tuple((hot[:, None, :] + around).reshape(-1, 3).T), shape))
    near = np.flatnonzero(np.isin(key, hot).reshape(2, -1).any(axis=0))

    def pairs(v: np.ndarray) -> set[tuple[int, int]]:
        return set(map(tuple, near[self_intersections(v, faces[near])].tolist()))

    return pairs(start), pairs(x)


class _Surface:
    """The posed surface the skin slides on: a moved point goes back to the closest point of the
    triangles near the one it lay on (`near` rings of faces), never across a crease to the other side."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray, near: int) -> None:
        self.vertices, self.faces, self.near = vertices, faces, near
        by_vertex = sp.csr_matrix((np.ones(faces.size), (faces.ravel(), np.repeat(np.arange(len(faces)), 3))),
                                  shape=(len(vertices), len(faces)))
        self.by_vertex = by_vertex
        self.touching = (by_vertex.T @ by_vertex).tocsr()  # faces sharing a vertex

    def start(self, idx: np.ndarray) -> np.ndarray:
        """(n,) a face each vertex `idx` lies on."""
        return self.by_vertex[idx].indices[self.by_vertex[idx].indptr[:-1]]

    def project(self, points: np.ndarray, on: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The closest points of the surface near faces `on` to `points` (n, 3), and the faces they lie on."""
        rows = self.touching[on]
        for _ in range(self.near - 1):
            rows = rows @ self.touching
        rows = rows.tocsr()
        owner = np.repeat(np.arange(len(on)), np.diff(rows.indptr))
        tri = self.vertices[self.faces[rows.indices]]
        closest = closest_points_on_triangles(points[owner], tri[:, 0], tri[:, 1], tri[:, 2])
        distance = np.linalg.norm(closest - points[owner], axis=1)
        first = nearest_in_groups(distance, rows.indptr)
        return closest[first], rows.indices[first]


def _relax(rest: np.ndarray, start: np.ndarray, faces: np.ndarray, free: np.ndarray, tilt: float, level: SlideLevel,
           carried: _Carried | None, tied: np.ndarray, slide: SlideSettings) -> tuple[np.ndarray, int]:
    """The local/global iteration with the `free` vertices of the skin `start` sliding, each tethered to where
    it lay `tied` (V,) times as hard as the level's tether: the slid skin and the steps taken. Its own
    triangles are limited, and so are the fine ones it carries, if any, which are the ones measured (the
    coarse skin is the contact's and the crossings' surface: none of its triangles may fold while the fine
    skin spreads)."""
    idx = np.flatnonzero(free)
    moving = faces[free[faces].any(axis=1)]
    g_own, area_own = _gradient_operator(rest, moving)
    own_free, own_fixed = g_own[:, idx], g_own @ start - g_own[:, idx] @ start[idx]
    if carried is None:  # the skin measured slides itself
        b, fixed_part, area, measured = own_free.tocsr(), own_fixed, area_own, len(area_own)
    else:  # (2Fa, nfree): the gradients' columns from the free vertices; (2Fa, 3): from all else
        w_free = carried.interpolation[:, idx].tocsc()
        touched = np.zeros(len(carried.vertices), dtype=bool)
        touched[np.unique(w_free.indices)] = True
        fine_moving = touched[carried.faces].any(axis=1)
        g_fine, area_fine = _gradient_operator(carried.rest, carried.faces[fine_moving])
        b = sp.vstack([g_fine @ w_free, own_free]).tocsr()
        fixed_part = np.concatenate([g_fine @ (carried.vertices - w_free @ start[idx]), own_fixed])
        area, measured = np.concatenate([area_fine, area_own]), len(area_fine)  # the first rows: the measured skin's
    bt = b.T.tocsr()
    tension, limit, done = slide.tension, slide.limit, slide.done
    tether = tension / level.falloff**2 * vertex_areas(rest, faces)[idx] * tied[idx]
    first = (fixed_part + b @ start[idx]).reshape(-1, 2, 3).transpose(0, 2, 1)
    # no triangle compressed below the floor by the sliding, nor more than it is (a crease's skin stays as short)
    floor = np.minimum(_svd(first)[1][:, 1], slide.floor)
    up = np.cross(first[:, :, 0], first[:, :, 1])  # each triangle's outward side as it lay
    sheet = triangle_normals(start[moving])  # as they lay (length: twice the area)
    smallest = level.shrink * np.minimum(np.linalg.norm(sheet, axis=1), np.linalg.norm(triangle_normals(rest[moving]), axis=1))
    surface = _Surface(start, faces, slide.near)
    on = surface.start(idx)
    facing = (lambda *_: sheet) if carried is not None else _surface_facing(surface, moving, idx)
    x = start.copy()
    over = np.zeros(len(area), dtype=bool)
    step, least, since = 0, np.inf, 0
    solve = SamePatternSolves()
    while step < slide.iterations and since < slide.stall:
        step += 1
        cols = fixed_part + b @ x[idx]
        f = cols.reshape(-1, 2, 3).transpose(0, 2, 1)  # (Fa, 3, 2)
        u, stretch, vt = _svd(f)
        over |= (stretch[:, 0] > limit) | (stretch.prod(axis=1) > limit)  # the limit's active set only grows
        beyond = float(area[:measured][(stretch[:measured, 0] > done) | (stretch[:measured].prod(axis=1) > done)].sum())
        if beyond == 0.0:
            break
        least, since = (beyond, 0) if beyond < least else (least, since + 1)
        target = _targets(f, u, stretch, vt, floor, up, over, slide)
        weight = np.repeat(area * (tension + over), 2)
        force = bt @ (weight[:, None] * (target.transpose(0, 2, 1).reshape(-1, 3) - cols)) \
            - tether[:, None] * (x[idx] - start[idx])  # (nfree, 3): −∂E/∂x
        weighted = bt.copy()  # bᵀ W
        weighted.data *= weight[bt.indices]
        stiffness = (weighted @ b + sp.diags(tether)).tocoo()  # (nfree, nfree): E's Hessian per coordinate
        tangents = _tangents(vertex_normals(x, moving)[idx])  # (nfree, 3, 2): x_i moves by T_i t_i
        normal = _tangent_hessian(stiffness, tangents)
        rhs = np.concatenate([np.einsum("ic,ic->i", tangents[:, :, k], force) for k in range(2)])
        t = solve(normal, rhs).reshape(2, -1).T  # (nfree, 2)
        move = np.einsum("ick,ik->ic", tangents, t)
        move *= np.minimum(1.0, slide.max_move / max(float(np.linalg.norm(move, axis=1).max()), 1e-300))
        trial, trial_on = surface.project(x[idx] + move, on)
        x[idx], on = _unfolded(x, idx, trial, on, trial_on, moving, facing, smallest, tilt, slide.hold_rounds)
        if np.linalg.norm(move, axis=1).max() < slide.stalled:
            break
    return x, step


def _tangent_hessian(stiffness: sp.coo_matrix, tangents: np.ndarray) -> sp.csc_matrix:
    """(2n, 2n) the Hessian `stiffness` (n, n; the same for x, y and z) in the vertices' tangent coordinates
    (`tangents` (n, 3, 2)): block (k, m) holds K_ij T_i[:, k]·T_j[:, m]."""
    i, j, n = stiffness.row, stiffness.col, stiffness.shape[0]
    dots = np.einsum("eck,ecm->ekm", tangents[i], tangents[j])  # (entries, 2, 2)
    rows = np.concatenate([i + k * n for k in range(2) for _ in range(2)])
    cols = np.concatenate([j + m * n for _ in range(2) for m in range(2)])
    values = np.concatenate([stiffness.data * dots[:, k, m] for k in range(2) for m in range(2)])
    return sp.csc_matrix((values, (rows, cols)), shape=(2 * n, 2 * n))


def _surface_facing(surface: _Surface, moving: np.ndarray, idx: np.ndarray
                    ) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
    """The way the skin's triangles `moving` should face when its vertices `idx` lie at points on the
    surface's faces `on` (the others where they are, on the surface's vertices): the surface's smooth normal
    (its vertex normals, interpolated: no choice among the faces round a vertex or an edge decides) under
    their corners, summed. The fine skin is what is measured: a fine triangle turned from the surface under
    it is skin folded over itself (its crossings); the coarse skin's triangles are held to how they lay
    instead (the armpit's hollow overhead has them turn)."""
    smooth = vertex_normals(surface.vertices, surface.faces)

    def facing(points: np.ndarray, on: np.ndarray) -> np.ndarray:
        under = smooth.copy()
        under[idx] = np.einsum("ij,ijk->ik", barycentric_on_triangles(points, surface.vertices[surface.faces[on]]),
                               smooth[surface.faces[on]])
        return under[moving].sum(axis=1)

    return facing


def _unfolded(x: np.ndarray, idx: np.ndarray, trial: np.ndarray, on: np.ndarray, trial_on: np.ndarray,
              faces: np.ndarray, facing: Callable[[np.ndarray, np.ndarray], np.ndarray], smallest: np.ndarray,
              tilt: float, rounds: int) -> tuple[np.ndarray, np.ndarray]:
    """The step to `trial` (the vertices `idx` of x, on the surface's faces `trial_on`), less the vertices
    of triangles (`faces`) it would turn beyond the cosine `tilt` from the way they should face (`facing`
    of where the vertices lie: (F, 3), any length) or shrink below `smallest` (twice the area): those stay (`rounds` times at most)."""
    out, out_on = trial.copy(), trial_on.copy()
    where = np.full(len(x), -1)
    where[idx] = np.arange(len(idx))
    for _ in range(rounds):
        y = x.copy()
        y[idx] = out
        normals = triangle_normals(y[faces])
        area = np.linalg.norm(normals, axis=1)
        sheet = facing(out, out_on)
        bad = (np.einsum("fi,fi->f", normals, sheet) < tilt * area * np.linalg.norm(sheet, axis=1)) \
            | (area < smallest)
        back = where[faces[bad].ravel()]
        back = back[back >= 0]
        if not len(back):
            break
        out[back], out_on[back] = x[idx][back], on[back]
    return out, out_on


def slide_posed_skin(fine: FineSkinning, pose: Pose, method: Skinning, rest: np.ndarray, coarse: np.ndarray,
                     faces: np.ndarray, settings: SkinSettings = SKIN_DEFAULTS) -> SkinSlide:
    """The coarse skin `coarse` of `pose` (posed by `method` plus an elastic displacement; `rest` at rest)
    slid (`slide_skin`; its fine skin is `fine`'s, carried as `FineSkinning.surface` carries it), then the
    fine skin it carries slid on its own (`slide_fine_skin`), as `settings.slide` says."""
    base = fine.surface(pose, method, np.zeros_like(coarse))  # the fine skin less the carried coarse skin
    layout = fine.fine
    slid = slide_skin(rest, coarse, faces, layout.vertices, layout.faces, layout.interpolation, base, settings,
                      layout.rest_frames)
    carried = fine.surface(pose, method, slid.vertices)  # as `ElasticPose.fine_vertices` carries it unslid
    return SkinSlide(slid, slide_fine_skin(layout.vertices, carried, layout.faces, settings, layout.rest_frames))
