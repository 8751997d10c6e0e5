"""The skin sliding over the fascia: stretch beyond what skin takes spread to the skin around it.

Skinning and the elastic body stretch the skin where a joint opens (the armpit overhead, the groin and
the buttock at hip flexion, the elbow's point) into bands of triangles stretched two to fifteen times,
where real skin slides over the fascia and spreads the stretch over a wide area, tethered to the fascia
by its fibrous septa (so the slide dies away from the opening joint). Here the posed coarse skin's
vertices near such bands slide within the posed surface, the shape unchanged, until the fine skin
(`hitogata.measure.fine_skin`, carried by the coarse skin through its Loop stencils) is stretched no
more than `DONE` along any direction nor in area.

The slid skin x minimises, over the free coarse vertices and on the posed surface,

    E(x) = Σ_f A_f (s ‖F_f − T_f‖² + h_f ‖F_f − L_f‖²) + Σ_i τ a_i ‖x_i − x⁰_i‖²,

F_f a triangle's deformation gradient from rest (rest area A_f; the fine triangles the free vertices
carry and the coarse triangles themselves), T_f its nearest gradient with no principal stretch above 1
(a tension-field membrane: skin resists stretch, not compression, which it takes in wrinkles; weight
`TENSION`), L_f its nearest gradient with principal stretches and area ratio at most `LIMIT` (weight
h_f = 1 once the triangle has been beyond it, else 0); both keep the smaller principal stretch at least
`FLOOR` (or what it was, if less: a crease's skin stays as short) and the triangle's side up. The
tether (the fascia) holds each vertex (rest area a_i) to where the contact left it, x⁰, with a stiffness
τ = s / `FALLOFF`²: a slide dies away over about `FALLOFF` from where the skin is pulled. It is solved by
local/global steps (the projections as in projective dynamics, Bouaziz et al. 2014, *Projective
Dynamics*, ACM TOG 33(4)): the local step projects every triangle (an SVD each, in closed form), the
global one solves the energy's quadratic model for the free vertices' moves along their tangent planes
(two unknowns a vertex, a sparse solve), then the vertices go back to the posed surface near where they
lay (never across a crease) and a move that would turn a coarse triangle over (`TILTS`) or shrink it
away (`SHRINK`) is left out there.

Free: the coarse skin within `REACH` (along the skin's edges) of the fine skin beyond `DONE`. If the
slid skin crosses itself where it did not (a slide across the bottom of a tight crease carries the
skin's chords through its other side), it slides again with less turning allowed, then with the skin
there held, and what still crosses has its slide undone.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.sparse.csgraph import dijkstra

from hitogata.geometry.mesh_checks import self_intersections
from hitogata.geometry.normals import vertex_normals
from hitogata.measure.fine_skin import FineSkinning
from hitogata.measure.strain import skin_strain
from hitogata.options import Skinning
from hitogata.skeleton.kinematics import Pose
from hitogata.volume.surface import closest_points_on_triangles

DONE = 1.95  # fine skin stretched beyond this (or its area) slides; the sliding ends when none is
LIMIT = 1.6  # principal stretch and area ratio an overstretched triangle is drawn back to
TENSION = 0.01  # weight of the tension-field membrane against the limit's (spreads stretch beyond the limit's band)
FALLOFF = 0.04  # m: the tether's reach: a slide dies away over about this distance
REACH = 0.15  # m: skin this far (along the edges) from skin beyond DONE is free to slide
FLOOR = 0.8  # smallest principal stretch the sliding may bring a triangle to
ITERATIONS = 80  # local/global steps at most
MAX_MOVE = 0.005  # m: the longest slide of a step (the surface's curvature and the flips stay in view)
STALLED = 2e-5  # m: the sliding ends when no vertex moves further in a step
NEAR = 2  # rings of faces around a vertex's face it may slide onto in one step
HOLD_ROUNDS = 3  # times skin that would cross is held and the rest slid again
# cosines: a slid coarse triangle turns at most this far from how it lay (154°: the armpit's hollow
# overhead needs it), or, if that slide crosses other skin, this far (90°: the groin's tight creases)
TILTS = (-0.9, 0.0)
STALL = 10  # steps without less fine skin beyond DONE: the sliding is held up (by the flips it may not make)
SHRINK = 0.2  # nor shrinks below this share of its area as it lay or at rest, whichever is less


@dataclass(frozen=True)
class SlideResult:
    """The slid coarse skin (V, 3), how far each vertex slid (V,) m, the free vertices (V,) bool, and the
    local/global steps taken."""

    vertices: np.ndarray
    moved: np.ndarray
    free: np.ndarray
    iterations: int


def _over(strain, limit: float) -> np.ndarray:
    return (strain.stretch_max > limit) | (strain.area_ratio > limit)


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
             over: np.ndarray) -> np.ndarray:
    """(F, 3, 2) each gradient's (f, its SVD u, s, vt) weighted target (s T + h L) / (s + h): T with
    principal stretches in [floor, 1], L in [floor, LIMIT] with area ratio ≤ LIMIT (h = 1 where `over`);
    a triangle slid over onto its back is turned back (its second direction reversed, at the floor)."""
    u, s = u.copy(), s.copy()
    flipped = np.einsum("fi,fi->f", np.cross(f[:, :, 0], f[:, :, 1]), up) < 0
    u[flipped, :, 1] *= -1.0
    s[flipped, 1] = floor[flipped]
    limited = np.clip(s, floor[:, None], LIMIT)
    limited *= np.minimum(1.0, np.sqrt(LIMIT / np.maximum(limited[:, :1] * limited[:, 1:], 1e-300)))
    hard = over.astype(float)
    weight = TENSION + hard
    target = (TENSION * np.clip(s, floor[:, None], 1.0) + hard[:, None] * limited) / weight[:, None]
    return np.einsum("fij,fj,fjk->fik", u, target, vt)


def _tangents(normals: np.ndarray) -> np.ndarray:
    """(n, 3, 2) two unit tangents per normal."""
    helper = np.where(np.abs(normals[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    u = np.cross(normals, helper)
    u /= np.linalg.norm(u, axis=1)[:, None]
    return np.stack([u, np.cross(normals, u)], axis=2)


def _vertex_areas(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    tri = vertices[faces]
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    return np.bincount(faces.ravel(), np.repeat(area / 3.0, 3), minlength=len(vertices))


def _edge_graph(vertices: np.ndarray, faces: np.ndarray) -> sp.csr_matrix:
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    length = np.linalg.norm(vertices[edges[:, 0]] - vertices[edges[:, 1]], axis=1)
    n = len(vertices)
    return sp.csr_matrix((length, (edges[:, 0], edges[:, 1])), shape=(n, n))


def slide_skin(rest: np.ndarray, coarse: np.ndarray, faces: np.ndarray, fine_rest: np.ndarray, fine_faces: np.ndarray,
               interpolation: sp.csr_matrix, fine_base: np.ndarray) -> SlideResult:
    """The coarse skin `coarse` (V, 3; `rest` at rest) slid within its surface until its fine skin
    (`fine_base + interpolation @ coarse`, rest `fine_rest`, `fine_faces`) is stretched at most `DONE`
    (principal stretch and area ratio); unchanged where none is beyond. Skin whose sliding would cross
    other skin (new self-crossing pairs, `self_intersections`; where the input crossed itself already,
    more pairs than it had) is held where it is, a ring around it too, and the rest slides again
    (`HOLD_ROUNDS` times at most; then the slide is undone around what still crosses)."""
    coarse = np.asarray(coarse, dtype=float)
    fine = fine_base + interpolation @ coarse
    over = _over(skin_strain(fine_rest, fine, fine_faces), DONE)
    n = len(coarse)
    if not over.any():
        return SlideResult(coarse, np.zeros(n), np.zeros(n, dtype=bool), 0)
    graph = _edge_graph(rest, faces)
    seeds = np.unique(np.asarray(interpolation[np.unique(fine_faces[over])].indices))
    free = np.isfinite(dijkstra(graph, directed=False, indices=seeds, limit=REACH, min_only=True))
    before = _pairs(coarse, faces)

    def crossing(x: np.ndarray) -> np.ndarray:
        """(V,) bool: the vertices of pairs crossing in x and not in the input, and a ring around them; none
        where the input crossed itself already and x crosses no more (the slide moved which pairs cross)."""
        after = _pairs(x, faces)
        new = np.array(sorted(after - before), dtype=np.int64).reshape(-1, 2)
        near = np.zeros(n, dtype=bool)
        if len(new) and not (before and len(after) <= len(before)):
            near[faces[new.ravel()].ravel()] = True
            near |= (graph + graph.T) @ near.astype(float) > 0
        return near

    tilts = (*TILTS, *[TILTS[-1]] * HOLD_ROUNDS)
    for rounds, tilt in enumerate(tilts):
        x, steps = _relax(rest, coarse, faces, free, fine, fine_rest, fine_faces, interpolation, tilt)
        held = crossing(x)
        if not held.any():
            return SlideResult(x, np.linalg.norm(x - coarse, axis=1), free, steps)
        if rounds >= len(TILTS) - 1:  # a gentler slide first, then the skin that crosses held
            free &= ~held
    while held.any():  # still crossing: the slide is undone around the crossings until none is left
        free &= ~held
        x[held] = coarse[held]
        held = crossing(x)
    return SlideResult(x, np.linalg.norm(x - coarse, axis=1), free, steps)


class _Surface:
    """The posed surface the skin slides on: a moved point goes back to the closest point of the
    triangles near the one it lay on (`NEAR` rings of faces), never across a crease to the other side."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray) -> None:
        self.vertices, self.faces = vertices, faces
        by_vertex = sp.csr_matrix((np.ones(faces.size), (faces.ravel(), np.repeat(np.arange(len(faces)), 3))),
                                  shape=(len(vertices), len(faces)))
        self.by_vertex = by_vertex
        touching = (by_vertex.T @ by_vertex).tocsr()  # faces sharing a vertex
        near = touching
        for _ in range(NEAR - 1):
            near = near @ touching
        self.near = near.tocsr()

    def start(self, idx: np.ndarray) -> np.ndarray:
        """(n,) a face each vertex `idx` lies on."""
        return self.by_vertex[idx].indices[self.by_vertex[idx].indptr[:-1]]

    def project(self, points: np.ndarray, on: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The closest points of the surface near faces `on` to `points` (n, 3), and the faces they lie on."""
        rows = self.near[on]
        owner = np.repeat(np.arange(len(on)), np.diff(rows.indptr))
        tri = self.vertices[self.faces[rows.indices]]
        closest = closest_points_on_triangles(points[owner], tri[:, 0], tri[:, 1], tri[:, 2])
        distance = np.linalg.norm(closest - points[owner], axis=1)
        order = np.lexsort((distance, owner))
        first = order[np.searchsorted(owner[order], np.arange(len(on)))]
        return closest[first], rows.indices[first]


def _pairs(x: np.ndarray, faces: np.ndarray) -> set[tuple[int, int]]:
    return set(map(tuple, self_intersections(x, faces).tolist()))


def _relax(rest: np.ndarray, coarse: np.ndarray, faces: np.ndarray, free: np.ndarray, fine: np.ndarray,
           fine_rest: np.ndarray, fine_faces: np.ndarray, interpolation: sp.csr_matrix, tilt: float
           ) -> tuple[np.ndarray, int]:
    """The local/global iteration with the `free` coarse vertices sliding: the slid skin and the steps
    taken. The fine triangles they carry are limited, and the coarse triangles too (the coarse skin is
    the contact's and the crossings' surface: none may fold while the fine skin spreads)."""
    idx = np.flatnonzero(free)
    w_free = interpolation[:, idx].tocsc()
    touched = np.zeros(len(fine), dtype=bool)
    touched[np.unique(w_free.indices)] = True
    fine_moving = touched[fine_faces].any(axis=1)
    g_fine, area_fine = _gradient_operator(fine_rest, fine_faces[fine_moving])
    moving = faces[free[faces].any(axis=1)]
    g_coarse, area_coarse = _gradient_operator(rest, moving)
    # (2Fa, nfree): the gradients' columns from the free coarse vertices; (2Fa, 3): from all else
    b = sp.vstack([g_fine @ w_free, g_coarse[:, idx]]).tocsr()
    fixed_part = np.concatenate([g_fine @ (fine - w_free @ coarse[idx]),
                                 g_coarse @ coarse - g_coarse[:, idx] @ coarse[idx]])
    area = np.concatenate([area_fine, area_coarse])
    tether = TENSION / FALLOFF**2 * _vertex_areas(rest, faces)[idx]
    start = (fixed_part + b @ coarse[idx]).reshape(-1, 2, 3).transpose(0, 2, 1)
    # no triangle compressed below FLOOR by the sliding, nor more than it is (a crease's skin stays as short)
    floor = np.minimum(_svd(start)[1][:, 1], FLOOR)
    up = np.cross(start[:, :, 0], start[:, :, 1])  # each triangle's outward side as it lay
    sheet = _normals(coarse, moving)  # as they lay (length: twice the area)
    smallest = SHRINK * np.minimum(np.linalg.norm(sheet, axis=1), np.linalg.norm(_normals(rest, moving), axis=1))
    n_fine = len(area_fine)
    surface = _Surface(coarse, faces)
    on = surface.start(idx)
    x = coarse.copy()
    over = np.zeros(len(area), dtype=bool)
    step, least, since = 0, np.inf, 0
    while step < ITERATIONS and since < STALL:
        step += 1
        cols = fixed_part + b @ x[idx]
        f = cols.reshape(-1, 2, 3).transpose(0, 2, 1)  # (Fa, 3, 2)
        u, stretch, vt = _svd(f)
        over |= (stretch[:, 0] > LIMIT) | (stretch.prod(axis=1) > LIMIT)  # the limit's active set only grows
        beyond = float(area_fine[(stretch[:n_fine, 0] > DONE) | (stretch[:n_fine].prod(axis=1) > DONE)].sum())
        if beyond == 0.0:
            break
        least, since = (beyond, 0) if beyond < least else (least, since + 1)
        target = _targets(f, u, stretch, vt, floor, up, over)
        weight = sp.diags(np.repeat(area * (TENSION + over), 2))
        force = b.T @ (weight @ (target.transpose(0, 2, 1).reshape(-1, 3) - cols)) \
            - tether[:, None] * (x[idx] - coarse[idx])  # (nfree, 3): −∂E/∂x
        stiffness = (b.T @ weight @ b + sp.diags(tether)).tocsr()  # (nfree, nfree): E's Hessian per coordinate
        tangents = _tangents(vertex_normals(x, faces)[idx])  # (nfree, 3, 2): x_i moves by T_i t_i
        scale = [[sp.diags(tangents[:, c, k]) for k in range(2)] for c in range(3)]
        normal = sp.bmat([[sum(scale[c][k] @ stiffness @ scale[c][m] for c in range(3)) for m in range(2)]
                          for k in range(2)]).tocsc()
        rhs = np.concatenate([np.einsum("ic,ic->i", tangents[:, :, k], force) for k in range(2)])
        t = spla.spsolve(normal, rhs).reshape(2, -1).T  # (nfree, 2)
        move = np.einsum("ick,ik->ic", tangents, t)
        move *= np.minimum(1.0, MAX_MOVE / max(float(np.linalg.norm(move, axis=1).max()), 1e-300))
        trial, trial_on = surface.project(x[idx] + move, on)
        x[idx], on = _unfolded(x, idx, trial, on, trial_on, moving, sheet, smallest, tilt)
        if np.linalg.norm(move, axis=1).max() < STALLED:
            break
    return x, step


def _normals(x: np.ndarray, faces: np.ndarray) -> np.ndarray:
    tri = x[faces]
    return np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])


def _unfolded(x: np.ndarray, idx: np.ndarray, trial: np.ndarray, on: np.ndarray, trial_on: np.ndarray,
              faces: np.ndarray, sheet: np.ndarray, smallest: np.ndarray, tilt: float) -> tuple[np.ndarray, np.ndarray]:
    """The step to `trial` (the vertices `idx` of x), less the vertices of coarse triangles (`faces`) it
    would turn beyond the cosine `tilt` from how they lay (`sheet`: their normals, length twice the area) or shrink
    below `smallest` (twice the area): those stay."""
    out, out_on = trial.copy(), trial_on.copy()
    where = np.full(len(x), -1)
    where[idx] = np.arange(len(idx))
    size = np.linalg.norm(sheet, axis=1)
    for _ in range(HOLD_ROUNDS):
        y = x.copy()
        y[idx] = out
        normals = _normals(y, faces)
        area = np.linalg.norm(normals, axis=1)
        bad = (np.einsum("fi,fi->f", normals, sheet) < tilt * area * size) | (area < smallest)
        back = where[faces[bad].ravel()]
        back = back[back >= 0]
        if not len(back):
            break
        out[back], out_on[back] = x[idx][back], on[back]
    return out, out_on


def slide_posed_skin(fine: FineSkinning, pose: Pose, method: Skinning, rest: np.ndarray, coarse: np.ndarray,
                     faces: np.ndarray) -> SlideResult:
    """`slide_skin` for the coarse skin `coarse` of `pose` (posed by `method` plus an elastic
    displacement; `rest` at rest): its fine skin is `fine`'s, carried as `FineSkinning.surface` carries it."""
    base = fine.surface(pose, method, np.zeros_like(coarse))  # the fine skin less the carried coarse skin
    return slide_skin(rest, coarse, faces, fine.fine.vertices, fine.fine.faces, fine.fine.interpolation, base)
