"""A garment's equilibrium in contact with a body: one barrier problem (IPC) solved by Newton.

The unknowns are the garment's in-plane coordinates (`tube.Tube.in_plane`)
and, for a soft body given its linear stiffness K, the body's free nodal
displacements u. Their energy

    E = W_garment(x) + ½ uᵀ K u + κ Σ b(d),

b the IPC log barrier of the squared distances d² between garment and body
surface within `DHAT` (the IPC Toolkit, `ipctk`, as the skin's self-contact
in `hitogata.geometry.barrier_contact`), is minimised by Newton: the
Hessian's barrier part projected to be positive semi-definite, every step
cut by continuous collision detection (the garment never passes through the
skin, nor the skin through the garment) and backtracked to decrease E. At
the minimum the barrier's forces are the contact forces: on the body's
surface nodes they are the interface pressure's resultant (`pressure`
divides them by each node's share of the skin's area).

The barrier's stiffness κ is set from the garment's own forces at the
start, so contact settles at about half the reach (within a knit's
thickness of the skin). A warm start (a motion's frame) carries the last
frame's κ, which may be too weak for the new posture's contacts: Newton
then drives a pair to CCD's gap, where no step may close it further. So κ
is raised along the way (IPC's adaptive stiffness, Li et al. 2020 §4.3, by
the IPC Toolkit's `update_barrier_stiffness`): doubled after a step that
brought the least distance below a tenth of the reach and closer than
before, and where CCD blocks a step at its gap. Once Newton has got past,
the answer is settled again at the start's κ, so that what is read does
not depend on the path's κ (a raised κ holds every contact further out,
the fabric stretched more: at four times κ the legging's ankle read 0.3
mmHg more).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cache
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from hitogata.errors import HitogataError
from hitogata.garment.contact.tube import Tube
from hitogata.geometry.ipc_toolkit import prepare_toolkit
from hitogata.options import FactorMethod

if TYPE_CHECKING:
    import ipctk

    from hitogata.garment.contact.readings import LevelReader

DHAT = 1e-3  # m: the barrier's reach, about a knit's thickness; the garment ends up within it of the skin
SETTLE = 0.5  # share of DHAT at which the start's garment forces would be balanced (sets κ)
CCD_GAP = 0.01 * DHAT  # m: CCD keeps garment and skin this far apart along a step
MAX_STEP = 0.005  # m: the longest vertex move of one Newton step (a trust region: CCD sees contact coming)
NEWTON = 200  # most Newton iterations
TOLERANCE = 1e-5  # m: a Newton step whose largest vertex move is below this has converged
# the Newton decrement −gᵀΔ below this share of the energy has converged (slow sliding into the facets of the
# skin's mesh then changes nothing a user reads)
DECREMENT = 1e-5
# a full Newton step of decrement below this share of the energy that changed no figure a user reads by more than
# its `readings.ReadTolerance` has converged (`settle`'s reader)
READ_DECREMENT = 1e-4
DAMPING = 1e-7  # Levenberg–Marquardt: × the Hessian's mean diagonal, for the garment's free sliding round a limb
FACTOR: FactorMethod | None = None  # the Newton step's factorization (None: the fastest installed, `factor_method`)
# a Newton step by conjugate gradients preconditioned with the last factored step's factors, to this residual
# relative to the gradient, while they take at most `REUSE_ITERATIONS` (0: every step factored; `_NewtonStep`):
# `INEXACT_FAR` where Newton watches the read figures and the last step's decrement was above `READ_DECREMENT` of
# the energy (an inexact Newton step: the path changes, the answer is held to what is read), else `INEXACT` (the
# equilibrium as tight as exact steps give it: the force balance to 1e-4)
INEXACT = 1e-2
INEXACT_FAR = 1e-1
REUSE_ITERATIONS = 25  # a coupled step's factorization costs about 30 of these iterations
PROBE_ITERATIONS = 4  # the first iterations, whose pace decides whether the rest are tried
# IPC's adaptive barrier stiffness (the IPC Toolkit's `update_barrier_stiffness`): κ doubled after a step that
# brought the least garment–body distance below this share of DHAT, closer than it was (CCD's gap is 0.01)
CLOSING = 0.1
# κ raised at most to this many times the answer's (the IPC Toolkit's ratio of its largest κ to its smallest)
STIFFEST = 100.0


@dataclass(frozen=True, eq=False)
class ContactBody:
    """The body a garment presses on: nodes (N, 3), outward surface triangles (S, 3) into them, and for a
    soft body its stiffness K (3N × 3N, node-major) with the held dofs (3N,) bool; rigid when K is None."""

    points: np.ndarray
    faces: np.ndarray
    stiffness: sp.csr_matrix | None = None
    fixed: np.ndarray | None = None

    @property
    def surface(self) -> np.ndarray:
        """The nodes on the surface (sorted)."""
        return np.unique(self.faces)


@dataclass(frozen=True, eq=False)
class Equilibrium:
    """The garment (V, 3) and body nodes (N, 3) at equilibrium, the contact force on each body node (N, 3)
    and on each garment vertex (V, 3) (N), the force holding each garment vertex in its plane (V, 3) (N: what
    friction on the skin must supply), Newton iterations, the least garment–skin distance (m), whether
    Newton converged and the barrier's stiffness κ it used."""

    garment: np.ndarray
    body: np.ndarray
    body_force: np.ndarray
    garment_force: np.ndarray
    held: np.ndarray  # (V, 3) N: the force holding each garment vertex in its ring's plane (along the tube)
    iterations: int
    min_distance: float
    converged: bool
    barrier_stiffness: float  # the barrier's κ of the answer
    start_stiffness: float  # the barrier's κ at the start (raised on the way where contacts kept closing: `settle`)


class _Problem:
    """The collision mesh (garment's vertices, then the body's surface nodes) and the unknowns' maps."""

    def __init__(self, tube: Tube, start: np.ndarray, body: ContactBody) -> None:
        import ipctk

        self.tube, self.body = tube, body
        self.n_garment = len(start)
        self.surface = body.surface
        local = np.full(len(body.points), -1)
        local[self.surface] = self.n_garment + np.arange(len(self.surface))
        faces = np.concatenate([tube.faces, local[body.faces]]).astype(np.int32)
        rest = np.concatenate([start, body.points[self.surface]])
        self.mesh = ipctk.CollisionMesh(rest, np.asarray(ipctk.edges(faces), dtype=np.int32), faces)
        patch = np.concatenate([np.zeros(self.n_garment), np.ones(len(self.surface))]).astype(np.int32)
        self.mesh.can_collide = ipctk.make_vertex_patches_filter(patch)
        self.ccd = ipctk.AdditiveCCD()
        # unknowns: in-plane garment coordinates (2V), then the body's free dofs
        self.garment_map = tube.in_plane()
        self.origin = start - (self.garment_map @ tube.stations.coordinates(
            start.reshape(tube.n_rings, tube.per_ring, 3)).reshape(-1)).reshape(-1, 3)
        n_dofs = 3 * len(body.points)
        if body.stiffness is None:
            self.free = np.zeros(0, dtype=np.int64)
        else:
            fixed = np.zeros(n_dofs, dtype=bool) if body.fixed is None else np.asarray(body.fixed, dtype=bool)
            self.free = np.flatnonzero(~fixed)
        self.stiffness = None if body.stiffness is None else body.stiffness[self.free][:, self.free].tocsr()
        # the collision vertices' positions for the unknowns: garment rows by the in-plane map, body rows by
        # picking the surface nodes' free dofs
        dof_column = np.full(n_dofs, -1)
        dof_column[self.free] = 2 * self.n_garment + np.arange(len(self.free))
        surface_dofs = (3 * self.surface[:, None] + np.arange(3)).ravel()
        picked = dof_column[surface_dofs] >= 0
        body_rows = sp.csr_matrix((np.ones(int(picked.sum())), (np.flatnonzero(picked), dof_column[surface_dofs][picked])),
                                  shape=(len(surface_dofs), 2 * self.n_garment + len(self.free)))
        garment_rows = sp.hstack([self.garment_map, sp.csr_matrix((3 * self.n_garment, len(self.free)))])
        self.jacobian = sp.vstack([garment_rows, body_rows]).tocsr()

    def positions(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The garment (V, 3) and the body's nodes (N, 3) for unknowns z."""
        garment = self.origin + (self.garment_map @ z[:2 * self.n_garment]).reshape(-1, 3)
        body = self.body.points.copy().ravel()
        body[self.free] += z[2 * self.n_garment:]
        return garment, body.reshape(-1, 3)

    def collision_vertices(self, garment: np.ndarray, body: np.ndarray) -> np.ndarray:
        return np.concatenate([garment, body[self.surface]])


def settle(tube: Tube, start: np.ndarray, body: ContactBody, dhat: float = DHAT, stiffness: float | None = None,
           iterations: int = NEWTON, tolerance: float = TOLERANCE, body_start: np.ndarray | None = None,
           reader: LevelReader | None = None, answer_stiffness: float | None = None,
           adaptive: bool = True) -> Equilibrium:
    """The garment's equilibrium from `start` (V, 3: on its rings' planes, free of crossings with the body
    and more than `CCD_GAP` from it, e.g. outside it) on `body` (its nodes from `body_start`, default their rest). stiffness: the barrier's κ
    (default: from the garment's forces at the start, see the module note). reader: what a user reads of
    the answer (the levels' pressures and indentations); Newton also stops where a full step of decrement
    under `READ_DECREMENT` of the energy changed none of them by more than its tolerance.

    Along the way κ is raised where contacts keep closing or CCD blocks a step (`_Newton.run`); the answer is
    then settled again from there at `answer_stiffness` (default the start's κ; infinite: kept as raised),
    so that it does not depend on the path's κ. Where that settle sticks (its equilibrium's contacts within
    CCD's gap), the raised κ's answer stands, its κ the `Equilibrium`'s `barrier_stiffness`. adaptive:
    False raises κ only where CCD blocks a step."""
    import ipctk

    prepare_toolkit()
    problem = _Problem(tube, np.asarray(start, dtype=float), body)
    coords = tube.stations.coordinates(np.asarray(start, dtype=float).reshape(tube.n_rings, tube.per_ring, 3))
    z = np.concatenate([coords.reshape(-1), np.zeros(len(problem.free))])
    if body_start is not None:
        z[2 * problem.n_garment:] = (np.asarray(body_start, dtype=float) - body.points).ravel()[problem.free]
    garment, nodes = problem.positions(z)
    v = problem.collision_vertices(garment, nodes)
    if ipctk.has_intersections(problem.mesh, v):
        raise HitogataError("garment: its start crosses the body's surface; allowed a start outside the body")
    membrane = tube.membrane
    if stiffness is None:
        forces = np.linalg.norm((problem.garment_map.T @ membrane.derivatives(garment)[1].ravel()).reshape(-1, 2), axis=1)
        typical = max(float(np.median(forces)), 1e-9)
        d = SETTLE * dhat
        stiffness = typical / (2 * d * abs(ipctk.barrier_first_derivative(d * d, dhat * dhat)))
    contacts = _collisions(problem, v, dhat)
    if len(contacts) and contacts.compute_minimum_distance(problem.mesh, v) <= CCD_GAP ** 2:
        # CCD could not move such a start at all (its step would be cut to nothing)
        raise HitogataError(f"garment: its start lies within {1e6 * CCD_GAP:.0f} µm of the body's surface; "
                            "allowed a start clear of it")
    newton = _Newton(problem, dhat, reader, tolerance, CLOSING if adaptive else 0.0)
    target = stiffness if answer_stiffness is None else answer_stiffness
    z, contacts, taken, converged, raised = newton.run(z, contacts, stiffness, iterations,
                                                       STIFFEST * min(stiffness, target), target)
    if converged and raised > target:
        again = newton.run(z, contacts, target, iterations - taken, target, np.inf)
        taken += again[2]
        if again[3]:
            z, contacts, _, _, raised = again
    garment, nodes = problem.positions(z)
    v = problem.collision_vertices(garment, nodes)
    force = -ipctk.BarrierPotential(dhat, raised).gradient(contacts, problem.mesh, v).reshape(-1, 3)
    body_force = np.zeros_like(body.points)
    body_force[problem.surface] = force[problem.n_garment:]
    gap = float(np.sqrt(contacts.compute_minimum_distance(problem.mesh, v))) if len(contacts) else dhat
    held = membrane.derivatives(garment)[1] - force[:problem.n_garment]  # balances the fabric's and the skin's pull
    return Equilibrium(garment, nodes, body_force, force[:problem.n_garment], held, taken, gap, converged, raised,
                       stiffness)


def _collisions(problem: _Problem, v: np.ndarray, dhat: float) -> ipctk.NormalCollisions:
    """The garment–body pairs within `dhat` at collision vertices `v`."""
    import ipctk

    c = ipctk.NormalCollisions()
    c.build(problem.mesh, v, dhat)
    return c


class _Newton:
    """Newton on one garment–body problem (see `settle`), its step's factors kept between its runs."""

    def __init__(self, problem: _Problem, dhat: float, reader: LevelReader | None, tolerance: float,
                 closing: float) -> None:
        self.problem, self.dhat, self.reader, self.tolerance = problem, dhat, reader, tolerance
        self.closing = closing  # share of dhat below which closing contacts raise κ (0: never)
        self.step = _NewtonStep()

    def energy(self, z: np.ndarray, contacts: ipctk.NormalCollisions, barrier: ipctk.BarrierPotential) -> float:
        problem = self.problem
        garment, nodes = problem.positions(z)
        e = problem.tube.membrane.energy(garment) + barrier(contacts, problem.mesh,
                                                            problem.collision_vertices(garment, nodes))
        if problem.stiffness is not None:
            u = z[2 * problem.n_garment:]
            e += 0.5 * float(u @ (problem.stiffness @ u))
        return e

    def run(self, z: np.ndarray, contacts: ipctk.NormalCollisions, stiffness: float, iterations: int,
            stiffest: float, settled_at: float) -> tuple[np.ndarray, ipctk.NormalCollisions, int, bool, float]:
        """Newton from unknowns `z` (their pairs `contacts`) with the barrier's κ `stiffness`, raised after a
        step that brought the least distance below `CLOSING` of the reach, closer than before (the IPC
        Toolkit's `update_barrier_stiffness`: IPC's adaptive κ), and doubled where CCD lets a step move no
        vertex by `tolerance` (a pair at its gap), up to `stiffest`: stuck there, not converged. While κ is above
        `settled_at` (the answer is then settled at that κ from here) the first full step of decrement under
        `READ_DECREMENT` of the energy ends it. Its unknowns and pairs at the end, the iterations taken,
        whether it converged (or ended so) and its κ at the end."""
        import ipctk

        problem, dhat, reader, tolerance = self.problem, self.dhat, self.reader, self.tolerance
        membrane = problem.tube.membrane
        barrier = ipctk.BarrierPotential(dhat, stiffness)
        garment, nodes = problem.positions(z)
        v = problem.collision_vertices(garment, nodes)
        diagonal = float(ipctk.world_bbox_diagonal_length(v))
        closest = contacts.compute_minimum_distance(problem.mesh, v) if len(contacts) else np.inf
        e0 = self.energy(z, contacts, barrier)
        n_g = 2 * problem.n_garment
        converged, taken = False, 0
        read: np.ndarray | None = None  # the read figures where the last step, a full one of small decrement, began
        near = False  # whether the last step's decrement was under READ_DECREMENT of the energy (then steps to INEXACT)
        while taken < iterations:
            taken += 1
            garment, nodes = problem.positions(z)
            v = problem.collision_vertices(garment, nodes)
            contact_gradient = barrier.gradient(contacts, problem.mesh, v)
            if reader is not None:
                reading = reader.read(garment, nodes, -contact_gradient.reshape(-1, 3)[:problem.n_garment])
                if read is not None and not reader.changed(read, reading):
                    converged = True
                    break
            _, g_membrane, h_membrane = membrane.derivatives(garment)
            gradient = problem.jacobian.T @ contact_gradient
            gradient[:n_g] += problem.garment_map.T @ g_membrane.ravel()
            h_barrier = barrier.hessian(contacts, problem.mesh, v, ipctk.PSDProjectionMethod.CLAMP)
            hessian = problem.jacobian.T @ h_barrier @ problem.jacobian
            blocks = [problem.garment_map.T @ h_membrane @ problem.garment_map]
            if problem.stiffness is not None:
                u = z[n_g:]
                gradient[n_g:] += problem.stiffness @ u
                blocks.append(problem.stiffness)
            hessian = (hessian + sp.block_diag(blocks)).tocsc()
            hessian = hessian + DAMPING * float(np.mean(np.abs(hessian.diagonal()))) * sp.identity(len(z), format="csc")
            step = self.step(hessian, gradient, INEXACT_FAR if reader is not None and not near else INEXACT)
            move = (problem.jacobian @ step).reshape(-1, 3)
            longest = float(np.linalg.norm(move, axis=1).max())
            if longest < tolerance or -float(gradient @ step) < DECREMENT * abs(e0):
                converged = True
                break
            scale = min(1.0, MAX_STEP / longest)
            step, move = step * scale, move * scale
            free = _collision_free(problem, v, v + move)
            alpha = min(1.0, free)
            if free < 1.0 and alpha * scale * longest < tolerance:
                # CCD allows next to no move: a pair at its gap that the step would close, κ too weak for its
                # force. κ doubled (up to `stiffest`) and Newton goes on from here; else stuck, not converged
                if stiffness >= stiffest:
                    break
                stiffness = min(stiffest, 2 * stiffness)
                barrier = ipctk.BarrierPotential(dhat, stiffness)
                e0, read = self.energy(z, contacts, barrier), None
                continue
            slope = float(gradient @ step)
            while True:
                trial = z + alpha * step
                tg, tn = problem.positions(trial)
                trial_v = problem.collision_vertices(tg, tn)
                contacts_trial = _collisions(problem, trial_v, dhat)
                e = self.energy(trial, contacts_trial, barrier)
                if alpha <= 1e-8 or e <= e0 + 1e-4 * alpha * slope:
                    break
                alpha *= 0.5
            near = -slope < READ_DECREMENT * abs(e0)
            full = alpha * scale == 1.0 and near
            read = reading if reader is not None and full else None
            z, e0, contacts = trial, e, contacts_trial
            if alpha * longest * scale < tolerance or (full and stiffness > settled_at):
                converged = True
                break
            last, closest = closest, (contacts.compute_minimum_distance(problem.mesh, trial_v) if len(contacts)
                                      else np.inf)
            raised = ipctk.update_barrier_stiffness(last, closest, stiffest, stiffness, diagonal,
                                                    self.closing * dhat / diagonal)
            if raised != stiffness:  # a new energy: its decrease and read figures start afresh
                stiffness, barrier = raised, ipctk.BarrierPotential(dhat, raised)
                e0, read = self.energy(z, contacts, barrier), None
        return z, contacts, taken, converged, stiffness


def _collision_free(problem: _Problem, v0: np.ndarray, v1: np.ndarray) -> float:
    """The share (0…1) of the way v0 → v1 free of crossings, garment and skin kept CCD_GAP apart."""
    import ipctk

    c = ipctk.Candidates()
    c.build(problem.mesh, v0, v1, CCD_GAP)
    return float(c.compute_collision_free_stepsize(problem.mesh, v0, v1, CCD_GAP, problem.ccd))


class _NewtonStep:
    """Newton's step −H⁻¹g, the Hessian's factors kept from step to step. The tissue's stiffness does not
    change between steps, the garment's and the barrier's little once the contacts are set, so a step is
    first sought by conjugate gradients preconditioned with the last factors, to `inexact` of the gradient
    (`settle` asks 1e-1 far from the equilibrium where it watches the read figures: a descent direction
    that changes the path; else 1e-2, the step's decrement within ~1e-4 of the exact step's). Each
    iteration costs a solve with the factors (~1/30 of a factorization): where the first
    `PROBE_ITERATIONS` do not reduce the residual at a pace that reaches `inexact` within
    `REUSE_ITERATIONS`, or those do not reach it, the step's own matrix is factored and kept."""

    def __init__(self) -> None:
        self.factors: Callable[[np.ndarray], np.ndarray] | None = None

    def __call__(self, hessian: sp.csc_matrix, gradient: np.ndarray, inexact: float = INEXACT) -> np.ndarray:
        from hitogata.fem.factor import factorize

        if self.factors is not None and REUSE_ITERATIONS > 0:
            step = self._reused(hessian, gradient, self.factors, inexact)
            if step is not None:
                return step
        self.factors = factorize(hessian, factor_method())
        return -np.asarray(self.factors(gradient))

    @staticmethod
    def _reused(hessian: sp.csc_matrix, gradient: np.ndarray, factors: Callable[[np.ndarray], np.ndarray],
                inexact: float) -> np.ndarray | None:
        """The step by conjugate gradients preconditioned with `factors`, or None where they no longer serve."""
        from scipy.sparse.linalg import LinearOperator, cg

        preconditioner = LinearOperator(hessian.shape, matvec=factors, dtype=float)
        probe = min(PROBE_ITERATIONS, REUSE_ITERATIONS)
        step, info = cg(hessian, -gradient, rtol=inexact, maxiter=probe, M=preconditioner)
        if info == 0:
            return np.asarray(step)
        residual = float(np.linalg.norm(hessian @ step + gradient) / np.linalg.norm(gradient))
        if residual ** (REUSE_ITERATIONS / probe) > inexact:  # too slow a pace to reach it within the budget
            return None
        step, info = cg(hessian, -gradient, x0=step, rtol=inexact, maxiter=REUSE_ITERATIONS - probe,
                        M=preconditioner)
        return np.asarray(step) if info == 0 else None


def factor_method() -> FactorMethod:
    """The factorization of a Newton step: `FACTOR`, or where it is None PARDISO's Cholesky if pypardiso is
    installed (it factors a soft limb's garment–tissue matrix, 25,000 unknowns with 16 million entries in
    SuperLU's factors, in 0.8 s against SuperLU's 1.7 s, the same step to 1e-14), else the project's default."""
    if FACTOR is not None:
        return FACTOR
    return "pardiso" if _pardiso_installed() else "auto"


@cache
def _pardiso_installed() -> bool:
    """Whether PARDISO loads here (asked once: a missing module is looked for again at every import)."""
    from hitogata.fem.factor import available_methods

    return "pardiso" in available_methods()


def crossings(garment: np.ndarray, garment_faces: np.ndarray, skin: np.ndarray, skin_faces: np.ndarray,
              gap: float = 0.0) -> bool:
    """Whether any garment triangle and skin triangle intersect (exact: the IPC Toolkit's test), or come
    within `gap` (m) of each other."""
    import ipctk

    prepare_toolkit()
    used = np.unique(skin_faces)
    local = np.full(len(skin), -1)
    local[used] = len(garment) + np.arange(len(used))
    faces = np.concatenate([garment_faces, local[skin_faces]]).astype(np.int32)
    vertices = np.concatenate([garment, skin[used]])
    mesh = ipctk.CollisionMesh(vertices, np.asarray(ipctk.edges(faces), dtype=np.int32), faces)
    patch = np.concatenate([np.zeros(len(garment)), np.ones(len(used))]).astype(np.int32)
    mesh.can_collide = ipctk.make_vertex_patches_filter(patch)
    if gap > 0 and len(_near_pairs(mesh, vertices, gap)):
        return True
    return bool(ipctk.has_intersections(mesh, vertices))


def _near_pairs(mesh: ipctk.CollisionMesh, vertices: np.ndarray, gap: float) -> ipctk.NormalCollisions:
    """The pairs of a collision mesh within `gap` of each other."""
    import ipctk

    c = ipctk.NormalCollisions()
    c.build(mesh, vertices, gap)
    return c
