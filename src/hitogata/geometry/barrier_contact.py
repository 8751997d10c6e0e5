"""The skin's self-contact as a barrier problem (IPC: Li et al. 2020, Incremental Potential Contact).

The contact method of the elastic body (`hitogata.skin.single_pose.elastic_pose(..., contact=True)`):
the skin near contact is the unknown x of one smooth minimisation,

    E(x) = ½ (x − y)ᵀ (I + k·L) (x − y) + ½ λ (V(x) − V(y))² + κ Σ b(d(x)),

y the posture's skin (elastic or skinned), L the skin's uniform graph Laplacian (a pushed region
carries its neighbours with it, as a membrane would), V the enclosed volume (y's counts an overlap
twice, so the tissue a contact presses aside comes back as a swelling of the free skin around it), b the
IPC log barrier (reach `BarrierSettings.dhat`) over the vertex–triangle and edge–edge distances of skin that may meet:
vertices of different contact groups (`hitogata.skin.contact`) more than `BarrierSettings.apart` apart at
rest, or of one group whose skin folds onto itself (`folding`: a crease) more than `same_apart` apart.
The barrier is infinite at contact, so a start free of crossings stays free when every Newton step is
cut short by continuous collision detection (CCD): the pose is reached along a path of postures (the
rest skin, skinned postures on the way, the target), each step started from the last one's minimum.

Distances, barrier derivatives, broad phase and CCD are the IPC Toolkit's (`ipctk`, MIT licence). The
unknowns are the skin near the contacts along the path (`BarrierSettings.reach` of another group, grown by
`rings` rings); the rest of the skin is the target's.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.spatial import cKDTree

from hitogata.errors import require, require_above, require_whole
from hitogata.geometry.contact import SelfContact
from hitogata.geometry.ipc_toolkit import prepare_toolkit

if TYPE_CHECKING:
    import ipctk  # imported where used: half a second, paid only when contact is resolved


@dataclass(frozen=True)
class BarrierSettings:
    """The barrier problem's constants, SI (m, m⁻⁴): how near skin comes, how hard it is pushed apart, which
    skin is free, and how the Newton steps are taken and stopped. Refused when out of range (`__post_init__`)."""

    dhat: float = 2e-3
    """m: the barrier's reach; skin in contact ends up within it."""
    same_apart: float = 0.03
    """m: skin of one group meets itself only if this far apart at rest (a crease folding onto itself)."""
    stiffness: float = 1e8
    """κ, the barrier's weight against the tracking energy (the toolkit's barrier is of squared distances,
    ~1e-8 at 1 mm)."""
    smoothing: float = 10.0
    """k, the Laplacian's weight in the tracking energy; a push spreads over ~√k rings."""
    reach: float = 0.02
    """m: a vertex this close to another group's vertex in the target may meet it (is free)."""
    rings: int = 3
    """rings of skin around those that may meet that are free to move too."""
    iterations: int = 60
    """most Newton iterations a step of the path."""
    incompressibility: float = 1e9
    """λ, m⁻⁴: weight of ½ (V − V_target)², the enclosed volume held to the target's (whose overlaps count
    twice: the tissue a contact presses aside comes back as a swelling of the free skin around it)."""
    tolerance: float = 5e-4
    """m: a Newton step whose largest vertex move is below this has converged (fine enough for a crease's flat
    energy: decision 0058)."""
    ccd_gap_share: float = 0.005
    """share of `dhat` that continuous collision detection keeps the skin apart along a step (`ccd_gap`): its
    time-of-impact tolerance is relative to the step, so a long step could otherwise end nanometres from
    contact, where the next CCD misses a crossing."""
    max_step: float = 0.1
    """m: the longest vertex move of one Newton step (a trust region: CCD then sees contact coming)."""
    sweep_pairs: int = 200_000
    """candidate pairs above which a CCD sweep is costly: when CCD let through under half of such a step, the
    next is offered at most twice the move let through (decision 0031: the female's crossed forearms swept
    21 M candidates, 9 s a step, for the move a 10 mm offer makes); a cheap sweep keeps the full offer."""
    min_step: float = 0.005
    """m: the smallest step the trust region offers after a costly cut step (ten times `tolerance`)."""

    def __post_init__(self) -> None:
        for name in ("dhat", "same_apart", "stiffness", "reach", "incompressibility", "tolerance", "ccd_gap_share",
                     "max_step", "min_step"):
            require_above(f"BarrierSettings.{name}", getattr(self, name))
        require(bool(np.isfinite(self.smoothing) and self.smoothing >= 0), "BarrierSettings.smoothing", self.smoothing,
                "a number at least 0")
        require(self.ccd_gap_share < 1, "BarrierSettings.ccd_gap_share", self.ccd_gap_share, "a share of dhat below 1")
        require(self.min_step <= self.max_step, "BarrierSettings.min_step", self.min_step,
                f"at most max_step ({self.max_step!r} m)")
        require_whole("BarrierSettings.rings", self.rings, 0)
        require_whole("BarrierSettings.iterations", self.iterations, 1)
        require_whole("BarrierSettings.sweep_pairs", self.sweep_pairs, 0)

    @property
    def apart(self) -> float:
        """m: primitives nearer than this at rest never collide (they would start inside the barrier): 2 dhat."""
        return 2 * self.dhat

    @property
    def ccd_gap(self) -> float:
        """m: CCD keeps the skin this far apart along a step (`ccd_gap_share` of `dhat`)."""
        return self.ccd_gap_share * self.dhat


BARRIER_DEFAULTS = BarrierSettings()


@dataclass(frozen=True)
class BarrierResult:
    """The resolved skin (V, 3), the free vertices, Newton iterations taken per path step, the
    smallest distance (m) between skin that may collide at the end, and the resolved skin at the
    path's last posture but one (V, 3: the start of the last step, free of crossings as it is)."""

    vertices: np.ndarray
    free: np.ndarray
    iterations: list[int]
    min_distance: float
    before_last: np.ndarray


def _grow(mask: np.ndarray, test: SelfContact, rings: int) -> np.ndarray:
    """`mask` (V,) bool grown by `rings` rings of the skin's neighbours."""
    out = mask.copy()
    for _ in range(rings):
        out = out | (test.neighbour_average @ out.astype(float) > 0)
    return out


def contact_regions(path: Sequence[np.ndarray], test: SelfContact, reach: float = BARRIER_DEFAULTS.reach,
                    rings: int = BARRIER_DEFAULTS.rings) -> np.ndarray:
    """(P, V) bool, a row for each of `path`'s P postures: the skin that may meet another group by that
    posture (at it or one before it, a vertex within `reach` of another group's vertex that lay at least
    `reach` further away at rest: contacts the posture brings, not the rest body's own; one of the two has
    moved by more than `reach`), grown by `rings`. The last row is all the path's. Searched group against
    group (a tree each, the pairs whose boxes come within `reach`): the skin's own neighbours, most of the
    pairs this near, are never looked at."""
    order = np.argsort(test.groups, kind="stable")
    bounds = np.searchsorted(test.groups[order], np.arange(test.n_groups + 1))
    starts = bounds[:-1][bounds[1:] > bounds[:-1]]  # the groups with skin, as runs of `order`
    members = np.split(order, starts[1:])
    near = np.zeros((len(path), len(test.rest)), dtype=bool)
    for step, target in enumerate(path):
        if step:
            near[step] = near[step - 1]
        moved = np.linalg.norm(target - test.rest, axis=1) > reach
        stirred = np.logical_or.reduceat(moved[order], starts)
        if not stirred.any():
            continue
        ordered = target[order]
        low = np.minimum.reduceat(ordered, starts) - reach
        high = np.maximum.reduceat(ordered, starts)
        meet = (low[:, None] <= high[None]).all(axis=2) & (low[None] <= high[:, None]).all(axis=2)
        meet = np.triu(meet & (stirred[:, None] | stirred[None]), 1)  # a pair only if one of them moved
        trees: dict[int, cKDTree] = {}
        for g, h in zip(*np.nonzero(meet)):
            for k in (g, h):
                if k not in trees:
                    trees[k] = cKDTree(target[members[k]])
            found = trees[g].sparse_distance_matrix(trees[h], reach, output_type="ndarray")
            i, j = members[g][found["i"]], members[h][found["j"]]
            keep = (moved[i] | moved[j]) & (np.linalg.norm(test.rest[i] - test.rest[j], axis=1) > found["v"] + reach)
            near[step, i[keep]] = True
            near[step, j[keep]] = True
    grown = near.copy()
    for step in range(len(path)):  # a row like the one before grows alike
        if step and np.array_equal(near[step], near[step - 1]):
            grown[step] = grown[step - 1]
        else:
            grown[step] = _grow(near[step], test, rings)
    return grown


def _factor(a: sp.spmatrix) -> spla.SuperLU:
    """The sparse LU of a symmetric positive definite matrix: symmetric ordering, no pivoting."""
    return spla.splu(a.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True})


def _trust_region(reach: float, offered: float, alpha: float, pairs: int, settings: BarrierSettings) -> float:
    """The next step's longest vertex move (m) after one offered `offered` (m, the trust region `reach`) of which
    CCD let the share `alpha` through, its sweep `pairs` candidate pairs: twice the move let through when under
    half was and the sweep was costly (`settings.sweep_pairs`), double after a full step that the region capped,
    else as it was."""
    if alpha < 0.5 and pairs > settings.sweep_pairs:
        return max(2.0 * alpha * offered, settings.min_step)
    if alpha >= 1.0 and offered >= reach:
        return min(2.0 * reach, settings.max_step)
    return reach


class _Problem:
    """The barrier problem on the free skin: its collision mesh, which of its primitive pairs may
    meet, the tracking energy's matrix."""

    def __init__(self, test: SelfContact, free: np.ndarray, settings: BarrierSettings, folding: Sequence[int]) -> None:
        import ipctk

        self.settings = settings
        # the collision mesh: the free skin's triangles, every vertex of them an unknown (a fixed
        # vertex would jump with its target, unchecked by CCD)
        faces = test.faces[free[test.faces[:, 0]] & free[test.faces[:, 1]] & free[test.faces[:, 2]]]
        self.vertices = np.unique(faces)  # global ids of the sub-mesh's vertices
        local = np.full(len(test.rest), -1)
        local[self.vertices] = np.arange(len(self.vertices))
        self.faces = local[faces].astype(np.int32)
        # the triangles whose volume the unknowns change: those with a corner in the sub-mesh (which
        # corners, and their local ids)
        touching = (local[test.faces[:, 0]] >= 0) | (local[test.faces[:, 1]] >= 0) | (local[test.faces[:, 2]] >= 0)
        self.touching = test.faces[touching]
        self.local_corners = local[self.touching]
        self.inside = self.local_corners >= 0
        # each unknown's share of the volume's gradient: the sum of b×c over the corners it is (T·3 → n)
        self.corner_rows = self.local_corners[self.inside]
        self.corner_sum = sp.csr_matrix((np.full(len(self.corner_rows), 1.0 / 6.0),
                                         (self.corner_rows, np.flatnonzero(self.inside.ravel()))),
                                        shape=(len(self.vertices), self.inside.size))
        self.rest = test.rest[self.vertices]
        self.edges = np.asarray(ipctk.edges(self.faces), dtype=np.int32)
        self.mesh = ipctk.CollisionMesh(self.rest, self.edges, self.faces)
        self.groups = test.groups[self.vertices].astype(np.int32)
        # which vertex pairs may meet: a folding group's vertices are each a patch of their own, the
        # others one patch per group; never a pair near at rest. The toolkit lets two primitives meet
        # when any of their vertex pairs may: a triangle reaching past `apart` (`same_apart`) from a vertex
        # meets it, which the rest skin's own spacing allows (nothing lies within the barrier at rest). The
        # pair map holds only the pairs the patches let through (the broad phase looks every overlapping
        # pair up in it: a hand's thousands of near pairs, one patch, made it slower by a third)
        n = len(self.vertices)
        folds = np.isin(self.groups, np.asarray(folding, dtype=np.int32))
        patch = np.where(folds, test.n_groups + np.arange(n), self.groups).astype(np.int32)
        close = cKDTree(self.rest).query_pairs(settings.same_apart, output_type="ndarray")
        close = close[patch[close[:, 0]] != patch[close[:, 1]]]
        same = self.groups[close[:, 0]] == self.groups[close[:, 1]]
        close = close[same | (np.linalg.norm(self.rest[close[:, 0]] - self.rest[close[:, 1]], axis=1) <= settings.apart)]
        self.mesh.can_collide = ipctk.make_vertex_patches_filter(patch) & ipctk.make_sparse_filter(
            dict.fromkeys(zip(close[:, 0].tolist(), close[:, 1].tolist()), False), True)
        self.dhat = settings.dhat
        self.barrier = ipctk.BarrierPotential(settings.dhat, settings.stiffness)
        self.ccd = ipctk.AdditiveCCD()  # Li et al. 2021: a third of the tight-inclusion CCD's cost here
        sub = (test.neighbour_average[self.vertices][:, self.vertices] > 0).astype(float)
        laplacian = sp.diags(np.asarray(sub.sum(axis=1)).ravel()) - sub
        a = (sp.identity(n) + settings.smoothing * laplacian).tocsr()
        self.tracking = sp.kron(a, sp.identity(3)).tocsr()  # dofs vertex-major (x0, y0, z0, x1, …), as ipctk's

    def candidates(self, x0: np.ndarray, x1: np.ndarray, within: float | None = None) -> ipctk.Candidates:
        """The primitive pairs that may meet and may come within `within` (default dhat) of each other on
        the way x0 → x1."""
        import ipctk

        c = ipctk.Candidates()
        c.build(self.mesh, x0, x1, self.dhat if within is None else within)
        return c

    def stepsize(self, candidates: ipctk.Candidates, x0: np.ndarray, x1: np.ndarray) -> float:
        """The share (0…1) of the way x0 → x1 free of crossings, the skin kept `ccd_gap` apart (`candidates`: the
        way's pairs; the additive CCD)."""
        return min(1.0, candidates.compute_collision_free_stepsize(self.mesh, x0, x1, self.settings.ccd_gap, self.ccd))

    def collisions(self, candidates: ipctk.Candidates, x: np.ndarray) -> ipctk.NormalCollisions:
        import ipctk

        c = ipctk.NormalCollisions()
        c.build(candidates, self.mesh, x, self.dhat)
        return c

    def volume(self, x: np.ndarray, target: np.ndarray, at_target: np.ndarray) -> tuple[float, np.ndarray]:
        """The enclosed volume's change (m³) from the target's triangles (`target`: (T, 3, 3), the
        touching triangles; `at_target`: their corners' triple products) with the sub-mesh at x, and its
        gradient (n, 3) in x."""
        moved = target.copy()
        moved[self.inside] = x[self.corner_rows]
        # b×c for each corner a (d(a·(b×c))/da, and so on round the corners)
        b, c = moved[:, [1, 2, 0]], moved[:, [2, 0, 1]]
        cross = np.stack([b[..., 1] * c[..., 2] - b[..., 2] * c[..., 1], b[..., 2] * c[..., 0] - b[..., 0] * c[..., 2],
                          b[..., 0] * c[..., 1] - b[..., 1] * c[..., 0]], axis=-1)
        change = (np.einsum("ij,ij->i", moved[:, 0], cross[:, 0]) - at_target).sum() / 6.0
        return float(change), self.corner_sum @ cross.reshape(-1, 3)

    def minimise(self, x: np.ndarray, target: np.ndarray, iterations: int, tolerance: float,
                 contacts: ipctk.NormalCollisions | None = None, swell: float = 0.0
                 ) -> tuple[np.ndarray, int, ipctk.NormalCollisions]:
        """Newton from x (free of crossings; `contacts`: its pairs within dhat, if known) towards the
        minimum for the whole skin's `target` (its enclosed volume plus `swell`), every step limited by
        CCD and backtracked to decrease the energy (the volume term Gauss–Newton, its rank-one Hessian by
        Sherman–Morrison); the minimum, the iterations taken and the minimum's pairs within dhat (the
        next step's start)."""
        import ipctk

        y = target[self.vertices]
        # a step that starts out of contact and meets nothing at the target (a static query, the cheaper) nor on
        # the way: the target as it is (a step in contact, or holding the volume, is solved)
        if not swell and (contacts is None or not len(contacts)):
            meeting = self.collisions(self.candidates(y, y), y)
            if not len(meeting) and self.stepsize(self.candidates(x, y), x, y) >= 1.0:
                return y.copy(), 0, meeting
        full = target[self.touching]
        at_target = np.einsum("ij,ij->i", full[:, 0], np.cross(full[:, 1], full[:, 2]))
        lam = self.settings.incompressibility

        def energy(x: np.ndarray, contacts: ipctk.NormalCollisions) -> tuple[float, np.ndarray, float, np.ndarray]:
            """E at x, with its tracking term's gradient, the volume's change and the volume's gradient."""
            d = (x - y).ravel()
            tracked = self.tracking @ d
            change, w = self.volume(x, full, at_target)
            change -= swell
            e = 0.5 * float(d @ tracked) + 0.5 * lam * change ** 2 + self.barrier(contacts, self.mesh, x)
            return e, tracked, change, w.ravel()

        x = x.copy()
        if contacts is None:
            contacts = self.collisions(self.candidates(x, x), x)
        e0, tracked, change, w = energy(x, contacts)
        taken = 0
        reach = self.settings.max_step  # the trust region: the longest vertex move offered to CCD
        while taken < iterations:
            taken += 1
            others = tracked + self.barrier.gradient(contacts, self.mesh, x)  # the gradient but the volume's
            gradient = others + lam * change * w
            hessian = self.barrier.hessian(contacts, self.mesh, x, ipctk.PSDProjectionMethod.CLAMP)
            h = _factor(self.tracking + hessian)
            # (H + λ w wᵀ) step = −(others + λ·ΔV·w) by Sherman–Morrison, the volume's large terms kept out of
            # the solves (solved with them, the step is a small difference of large vectors)
            u, v = h.solve(-others), h.solve(w)
            step = (u - v * (lam * (change + w @ u) / (1.0 + lam * (w @ v)))).reshape(-1, 3)
            longest = float(np.linalg.norm(step, axis=1).max())
            if longest < tolerance:
                break
            step *= min(1.0, reach / longest)
            # the sweep's pairs within the CCD's gap only (within dhat, the crease's skin lying a few mm apart
            # over wide areas, they were 2-3x as many on a short step, half again on a long one); the
            # contacts of a trial then from a static query of its own
            swept = self.candidates(x, x + step, self.settings.ccd_gap)
            alpha = cut = self.stepsize(swept, x, x + step)
            reach = _trust_region(reach, min(longest, reach), alpha, len(swept), self.settings)
            slope = float(gradient @ step.ravel())
            while True:  # backtracking (Armijo) within the collision-free part of the step
                trial = x + alpha * step
                contacts = self.collisions(self.candidates(trial, trial), trial)  # kept for the next iteration
                e, t, ch, wt = energy(trial, contacts)
                if alpha <= 1e-6 or e <= e0 + 1e-4 * alpha * slope:
                    break
                alpha *= 0.5
            x, e0, tracked, change, w = trial, e, t, ch, wt
            # a short move has converged when it is Newton's own step, or when no step decreases the energy; a
            # short move that CCD cut stops at a contact the barrier has not yet felt: the next step turns away
            if alpha * np.abs(step).max() < tolerance and (cut >= 1.0 or alpha <= 1e-6):
                break
        return x, taken, contacts

    def min_distance(self, x: np.ndarray, contacts: ipctk.NormalCollisions) -> float:
        """The smallest distance (m) between skin that may meet at x (`contacts`: x's pairs within dhat)."""
        return float(np.sqrt(contacts.compute_minimum_distance(self.mesh, x))) if len(contacts) else self.dhat


def barrier_resolve(path: Sequence[np.ndarray], test: SelfContact, settings: BarrierSettings = BARRIER_DEFAULTS,
                    folding: Sequence[int] = (), swell: float = 0.0, free: np.ndarray | None = None,
                    resumed: bool = False) -> BarrierResult:
    """The skin at the last of `path`'s postures (each (V, 3); the first should be free of crossings,
    e.g. the rest skin), with no skin of one contact group passing into another's: each posture in
    turn is the target y of the barrier problem, started from the previous solution, with the constants of `settings`. swell (m³): the
    last step holds the enclosed volume at V(y) + swell (the volume a crease gives up, back round it);
    free (steps, V) bool: each step's unknowns, if already found (default: `contact_regions` of the path:
    the skin that may meet other skin by that step; the rest takes the step's posture, as skin that may
    meet nothing takes it); resumed: the first posture is a `before_last` of a barrier on the same free
    skin, not checked again (the toolkit's intersection test finds crossings in it where skin that the
    barrier does not hold apart, one group's skin near at rest, crosses: the female hip flexion 120°)."""
    import ipctk

    prepare_toolkit()
    free = contact_regions(path[1:], test, settings.reach, settings.rings) if free is None else free
    steps = len(path) - 1
    skin = np.array(path[0], dtype=float)  # the whole skin where the path has taken it
    before, taken, problem, unknowns = skin, [], None, np.zeros(len(skin), dtype=bool)
    contacts: ipctk.NormalCollisions | None = None
    for k, (y, step_free) in enumerate(zip(path[1:], free), 1):
        before = skin
        if (step_free & ~unknowns).any():  # skin comes near other skin: a problem for all that may meet by now
            problem, unknowns, contacts = _Problem(test, step_free, settings, folding), step_free, None
            if not (resumed and k == 1) and ipctk.has_intersections(problem.mesh, skin[problem.vertices]):
                if k == 1:
                    raise ValueError("the path's first skin passes through itself where skin may meet: "
                                     "no barrier can start there")
                # skin that took its postures unchecked crosses where it joins the unknowns: every step with
                # all of them, as from the path's start
                return barrier_resolve(path, test, settings, folding, swell, np.broadcast_to(free[-1], free.shape),
                                       resumed)
        skin = np.array(y, dtype=float)
        if problem is None:  # nothing comes near other skin yet: the posture as it is
            taken.append(0)
            continue
        x, n, contacts = problem.minimise(before[problem.vertices], skin, settings.iterations, settings.tolerance, contacts,
                                          swell if k == steps else 0.0)
        skin[problem.vertices] = x
        taken.append(n)
    gap = settings.dhat if problem is None or contacts is None else problem.min_distance(skin[problem.vertices], contacts)
    return BarrierResult(skin, free[-1], taken, gap, before)
