"""The tissue's quasi-static answer to the bones: rotation-invariant elasticity on one prefactored matrix.

Skinning puts the nodes at g (bone nodes exactly with their parts), but
skinning is not mechanics: at a 150° elbow or an 80° trunk flexion it loses
up to a fifth of a region's volume and folds elements inside out. The tissue
settles instead to the minimiser of

    E(x) = Σ_elements Σ_quadrature  w V μ ‖F(x) − R‖²  −  fᵀ x,    R = the rotation nearest F,

with the bone nodes held where the skeleton puts them and each soft tissue
region's volume held at its rest value (the tissue is nearly incompressible:
ν = 0.49 in the shipped materials). The energy is the co-rotational
("as-rigid-as-possible") shear energy: it is zero for any rigid motion
however large, equals linear elasticity with shear modulus μ for small
strains, and its minimisation alternates two exact steps (local/global,
as in projective dynamics):

- local: R at every quadrature point, the proper rotation nearest F
  (`rotations.extract_rotations`; for det F < 0 the SVD's with its smallest
  direction flipped), so an inverted element is pulled back out instead of
  being read as a reflection;
- global: x from L x = b(R) + f/2 with L = Σ w V μ ∇N_a·∇N_b, a scalar
  Laplacian-like matrix that never changes: it is factored once, and each
  step is three back-substitutions (x, y, z share it).

Region volumes enter as Lagrange multipliers — a uniform pressure per
region — solved from the linearised constraints after each global step
(one more back-substitution, all regions and axes at once). A motion's
steps are Anderson-accelerated and start from the previous frame's answer:
its positions (the caller's `start`) and its rotations (a `WarmStart`, which
the caller makes with `warm_start()` and hands from solve to solve; a solve
given none starts from rest), so a few per frame suffice. A held posture
is solved from rest until its steps converge, Chebyshev-accelerated: the
least-squares mixing there ended where the last digits of the input sent
them, the skin centimetres apart (docs/decisions/0061-a-held-posture-that-converges.md);
fixed Chebyshev weights converge it in a third to half of the plain steps
to the plain steps' own equilibrium (docs/decisions/0062-a-held-posture-by-chebyshev-steps.md).

Elements kept right side out (a floor, not a guarantee): after the
accelerated steps, while some element's corner volume is below FLOOR x its
rest volume, up to REPAIRS further steps add those elements' volumes as
further multipliers (an inequality: one the floor would pull down is let
go), each projection capped at STEP_CAP per node (a flat element's
linearisation is poor), then the regions' volumes restored exactly. The
few elements that deep creases leave below the floor after that are lifted
by moving single nodes (`untangle`). A pose with no such element costs two
volume checks. A held element's volume gradient touches its four corners
only, so the Laplacian's response to it is combined from columns of L⁻¹
kept per node (`fem.factor.InverseColumns`): a repair step costs the
regions' back-substitutions whatever the number of elements held
(docs/decisions/0059-floor-repairs-from-kept-columns.md). The repair
steps also go on converging the whole body, so a motion's frames accelerate
them as the steps before them, the history restarted whenever the held set
changes, and stop when a step moves no node by more than the tolerance
(docs/decisions/0011-quasi-statics-floor-repairs-accelerated.md).

The solve runs on the elements' corner (linear) mesh: the correction is
smooth, the shear-only energy does not lock, and it is ~10x cheaper than on
the quadratic mesh; the dynamics lift it to the mid-edge nodes.

Speed: the deformation gradients and the global step's right side are
fixed sparse maps of the positions and the rotations, the rotations are
extracted on component arrays (`rotations.extract_rotations`), the volumes
and their gradients too (`volumes`), and the factor's triangular solves run
with BLAS held to one thread (docs/decisions/0008-blas-on-one-thread-in-small-solves.md).
A local/global step on the whole default body costs ~9 ms of one core;
docs/scenarios.md has the per-pose figures.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from threadpoolctl import threadpool_limits

from hitogata.geometry.rotations import extract_rotations
from hitogata.dynamics.untangle import Untangler
from hitogata.dynamics.volumes import corner_volumes, volumes_and_gradients
from hitogata.fem.elements import element_order, quadrature, shape_gradients, tet_geometry
from hitogata.fem.factor import InverseColumns, factorize
from hitogata.fem.materials import lame, per_element
from hitogata.options import FactorMethod

MEMORY = 5  # Anderson acceleration: past steps mixed
REPAIRS = 30  # at most so many steps after the last one holding elements over the floor
STEP_CAP = 0.02  # m: the largest node move of one projection while elements are held over the floor
FLOOR = 0.02  # an element's corner volume is held at least at this share of its rest volume


def rotate(rotations: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """R v row by row: rotations (..., 3, 3), vectors (..., 3)."""
    return np.einsum("...ij,...j->...i", rotations, vectors)


def unrotate(rotations: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """Rᵀ v row by row."""
    return np.einsum("...ji,...j->...i", rotations, vectors)


@dataclass(frozen=True)
class Anderson:
    """Anderson acceleration (Walker & Ni 2011; for local/global solvers Peng et al. 2018): each step's
    answer mixed with the last `memory` by least squares. The slow, bending-like error fields fall several
    times faster than under plain steps, which a motion's few steps a frame, started from the last frame's
    answer, need; the least squares on nearly dependent residuals carry round-off into the answer, so a
    held posture solved from rest takes `Chebyshev` instead."""

    memory: int = MEMORY


@dataclass(frozen=True)
class Chebyshev:
    """Chebyshev semi-iterative acceleration (Wang 2015, "A Chebyshev semi-iterative approach for
    accelerating projective and position-based dynamics"): after `plain_steps` plain steps, each step's
    answer is extrapolated from the iterate two steps back by the weights of the Chebyshev polynomials for
    an iteration contracting at `spectral_radius`. Fixed weights: the answer is as smooth a function of the
    input as plain steps' (a round-off nudge moves it by about the nudge), in a third to half of their
    steps. The radius is the plain steps' slowest rate on the default bodies' extreme poses (0.97-0.995 a
    step); more extrapolation (0.99) lands the male trunk flexion in another fold of the belly
    (docs/decisions/0062-a-held-posture-by-chebyshev-steps.md)."""

    spectral_radius: float = 0.97
    plain_steps: int = 10

    def __post_init__(self) -> None:
        if not 0.0 < self.spectral_radius < 1.0 or self.plain_steps < 1:
            raise ValueError(f"Chebyshev: spectral_radius {self.spectral_radius} must lie in (0, 1) and "
                             f"plain_steps {self.plain_steps} be at least 1")

    def weight(self, step: int, previous: float) -> float:
        """The extrapolation weight ω of step `step` (from 0), given the previous step's."""
        if step < self.plain_steps:
            return 1.0
        rho2 = self.spectral_radius**2
        return 2.0 / (2.0 - rho2) if step == self.plain_steps else 4.0 / (4.0 - rho2 * previous)


Acceleration = Anderson | Chebyshev | None  # None: plain local/global steps
FRAME = Anderson()  # a motion's frame, started from the last frame's answer
HELD = Chebyshev()  # a held posture solved from rest


@dataclass(eq=False)
class WarmStart:
    """What one quasi-static solve hands the next: the local step's rotations, as quaternions (4, M)
    per quadrature point. Made by `QuasiStatic.warm_start` (at rest: identity); a solve given one
    starts from it and leaves its own answer in it; a solve given none starts from rest."""

    quaternions: np.ndarray


class QuasiStatic:
    """Local/global solver of the tissue's equilibrium about a posed skeleton (see the module note)."""

    def __init__(self, points: np.ndarray, elements: np.ndarray, E: np.ndarray | float, nu: np.ndarray | float,
                 fixed_nodes: np.ndarray, region: np.ndarray, constrained_regions: tuple[int, ...],
                 method: FactorMethod = "auto") -> None:
        self.points = np.asarray(points, dtype=float)
        self.elements = np.asarray(elements)
        self.region = np.asarray(region)
        self.constrained = tuple(int(r) for r in constrained_regions)
        n, t = len(self.points), len(self.elements)
        order = element_order(self.elements)
        bary, w = quadrature(2 * (order - 1))
        grads_l, vol = tet_geometry(self.points, self.elements)
        grads = shape_gradients(order, bary, grads_l)  # (T, Q, n, 3)
        _, mu = lame(per_element(t, E, "E"), per_element(t, nu, "nu"))
        weights = (w[None, :] * vol[:, None]) * mu[:, None]  # (T, Q): w V mu
        a = np.einsum("tq,tqai,tqbi->tab", weights, grads, grads, optimize=True)
        rows = np.repeat(self.elements, self.elements.shape[1], axis=1).ravel()
        cols = np.tile(self.elements, (1, self.elements.shape[1])).ravel()
        lap = sp.csr_matrix((a.ravel(), (rows, cols)), shape=(n, n))
        mask = np.ones(n, dtype=bool)
        mask[np.asarray(fixed_nodes)] = False
        self.free, self.fixed = np.flatnonzero(mask), np.asarray(fixed_nodes)
        self._lap_fb = lap[self.free][:, self.fixed]
        self._solve = factorize(lap[self.free][:, self.free], method)
        self._inverse_columns = InverseColumns(self._solve, len(self.free))
        # The local step as sparse maps (M = T Q quadrature points, rows ordered (i, m)):
        # F[j, i, m] = Σ_n x[n, j] ∂N_n/∂X_i at m, and the global step's right side
        # b[n, j] = Σ_m,i w_m R[j, i, m] ∂N_n/∂X_i (the free nodes' rows only).
        m = t * len(w)
        self.n_points = m
        point = np.repeat(np.arange(m), self.elements.shape[1])
        node = np.repeat(self.elements, len(w), axis=0).ravel()
        g = grads.reshape(m, -1, 3)
        self._gradient = sp.csr_matrix((np.concatenate([g[..., i].ravel() for i in range(3)]),
                                        (np.concatenate([point + i * m for i in range(3)]), np.tile(node, 3))),
                                       shape=(3 * m, n))
        self._gradient_free_t = self._gradient[:, self.free].T.tocsr()
        self._weights = weights.ravel()
        # each constrained region's volume gradient: corners (a, t) summed into (region, free node) rows
        corners = self.elements[:, :4]
        which = np.full(int(self.region.max(initial=0)) + 1, -1)
        which[list(self.constrained)] = np.arange(len(self.constrained))
        self._region_index = np.where(which[self.region] >= 0, which[self.region], len(self.constrained))
        column = np.full(n, -1)
        column[self.free] = np.arange(len(self.free))
        self._free_column = column
        entry = (column[corners.T] >= 0) & (self._region_index < len(self.constrained))[None, :]  # (4, T)
        corner_t = np.broadcast_to(np.arange(t), (4, t))
        self._region_gather = sp.csr_matrix(
            (np.ones(int(entry.sum())),
             (self._region_index[corner_t[entry]] * len(self.free) + column[corners.T][entry],
              (np.arange(4)[:, None] * t + corner_t)[entry])),
            shape=(len(self.constrained) * len(self.free), 4 * t))
        self.rest_volumes = self.region_volumes(self.points)
        self.rest_element_volumes = corner_volumes(self.points, self.elements)
        # elements with a free corner: those whose volume the floor can hold
        self._movable = np.isin(self.elements[:, :4], self.free).any(axis=1)
        self.untangle = Untangler(self.points, self.elements, mask, FLOOR)

    def warm_start(self) -> WarmStart:
        """A warm start at rest (every rotation the identity), to be handed from solve to solve."""
        q = np.zeros((4, self.n_points))
        q[0] = 1.0
        return WarmStart(q)

    def region_volumes(self, x: np.ndarray) -> np.ndarray:
        """Volume (m³) of each constrained region at node positions x (corner tets)."""
        v = corner_volumes(x, self.elements)
        return np.bincount(self._region_index, v, minlength=len(self.constrained) + 1)[:len(self.constrained)]

    def _volume_gradients(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Each constrained region's volume (regions,) at x and its derivative by the free nodes'
        positions (regions, free nodes, 3)."""
        v, g = volumes_and_gradients(x, self.elements)
        volumes = np.bincount(self._region_index, v, minlength=len(self.constrained) + 1)[:len(self.constrained)]
        return volumes, np.stack([self._region_gather @ g[k].ravel() for k in range(3)], axis=-1).reshape(
            len(self.constrained), len(self.free), 3)

    def _local(self, x: np.ndarray, warm: WarmStart) -> np.ndarray:
        """The global step's right side at the free nodes (free, 3) from the rotations nearest F(x)."""
        m = self.n_points
        F = np.ascontiguousarray((self._gradient @ x).reshape(3, m, 3).transpose(2, 0, 1))  # (j, i, m)
        R = extract_rotations(F, warm.quaternions)
        R *= self._weights
        return self._gradient_free_t @ R.transpose(1, 2, 0).reshape(3 * m, 3)

    def step(self, x: np.ndarray, loads: np.ndarray | None, warm: WarmStart,
             active: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray | None]:
        """One local/global iteration from node positions x (N, 3); bone nodes keep their positions.

        active: None, or the elements held at the volume floor so far in this solve (the step adds
        those it finds under it and returns the updated set)."""
        b = self._local(x, warm) - self._lap_fb @ x[self.fixed]
        if loads is not None:
            b += 0.5 * loads[self.free]
        new = x.copy()
        new[self.free] = self._solve(np.ascontiguousarray(b))
        return self._project(new, active)

    def _floor_violations(self, x: np.ndarray) -> np.ndarray:
        """Movable elements whose corner volume at x is below the floor."""
        v = corner_volumes(x, self.elements)
        return np.flatnonzero((v < FLOOR * self.rest_element_volumes) & self._movable)

    def _project(self, new: np.ndarray, active: np.ndarray | None) -> tuple[np.ndarray, np.ndarray | None]:
        """Enforce the linearised constraints at `new`: each region's rest volume, and the volume
        floor of the active elements (those that have fallen below it in this solve), by one
        multiplier each (a pressure), the Laplacian's response L⁻¹g solved by back-substitution for a
        region's gradient and combined from the kept columns of L⁻¹ at an element's four corners."""
        if active is not None:
            active = np.union1d(active, self._floor_violations(new))
        held = 0 if active is None else len(active)
        if not self.constrained and not held:
            return new, active
        regions = len(self.constrained)
        coupling = np.zeros((regions + held, regions + held))
        targets = []
        move = np.zeros((len(self.free), 3))
        if regions:
            volumes, gradients = self._volume_gradients(new)  # (regions, free, 3)
            region_response = self._response(gradients)
            coupling[:regions, :regions] = np.einsum("rfk,sfk->rs", gradients, region_response)
            targets.append(self.rest_volumes - volumes)
        if active is not None and held:
            corners = self.elements[active, :4]
            volumes, gradients = volumes_and_gradients(new, corners)  # (held,), (3, 4, held)
            columns = self._free_column[corners]  # (held, 4); a bone node's gradient is dropped
            gradients = np.where(columns.T[None] >= 0, gradients, 0.0).transpose(2, 1, 0)  # (held, 4, 3)
            columns = np.maximum(columns, 0)
            element_response = np.einsum("fea,eak->efk", self._inverse_columns(columns), gradients)
            coupling[regions:, regions:] = np.einsum("efak,fak->ef", element_response[:, columns], gradients)
            if regions:
                coupling[:regions, regions:] = np.einsum("rfak,fak->rf", region_response[:, columns], gradients)
                coupling[regions:, :regions] = coupling[:regions, regions:].T
            targets.append(FLOOR * self.rest_element_volumes[active] - volumes)
        p = np.linalg.lstsq(coupling, np.concatenate(targets), rcond=1e-12)[0]
        if regions:
            move += np.einsum("r,rfk->fk", p[:regions], region_response)
        if active is not None and held:
            move += np.einsum("r,rfk->fk", p[regions:], element_response)
        if active is not None and held:  # the floor is an inequality: an element it would pull down is let go
            active = active[p[regions:] >= 0.0]
        new = new.copy()
        if active is not None and len(active):  # a flat element's linearisation is poor: no node moves
            move *= min(1.0, STEP_CAP / max(float(np.abs(move).max()), 1e-30))  # more than STEP_CAP,
            new[self.free] += move
            if self.constrained:  # and the regions' volumes are then restored exactly
                volumes, gradients = self._volume_gradients(new)
                response = self._response(gradients)
                coupling = np.einsum("rfk,sfk->rs", gradients, response)
                new[self.free] += np.einsum("r,rfk->fk", np.linalg.solve(coupling, self.rest_volumes - volumes),
                                            response)
            return new, active
        new[self.free] += move
        return new, active

    def _response(self, gradients: np.ndarray) -> np.ndarray:
        """L⁻¹ g for each constraint gradient g (constraints, free, 3), all constraints and axes in one
        back-substitution: (constraints, free, 3)."""
        m = len(gradients)
        out = self._solve(np.ascontiguousarray(gradients.transpose(1, 2, 0).reshape(len(self.free), 3 * m)))
        return out.reshape(len(self.free), 3, m).transpose(2, 0, 1)

    def solve(self, x: np.ndarray, loads: np.ndarray | None = None, iterations: int = 8,
              tolerance: float = 1e-5, warm: WarmStart | None = None,
              acceleration: Acceleration = FRAME) -> tuple[np.ndarray, float]:
        """Node positions (N, 3) after at most `iterations` steps from x, and the last step's size (m).

        warm: the rotations to start the local steps from, updated to this solve's (None: from rest).
        acceleration: `Anderson` (a motion's frames), `Chebyshev` (`HELD`: a held posture from rest; its
        floor repairs are plain steps) or None (plain steps). Stops early when a step moves no node by
        more than `tolerance`.
        """
        warm = self.warm_start() if warm is None else warm
        with threadpool_limits(1):  # small solves: BLAS threads only wait on each other on a busy machine
            return self._solve_steps(x, loads, iterations, tolerance, warm, acceleration)

    def _solve_steps(self, x: np.ndarray, loads: np.ndarray | None, iterations: int, tolerance: float,
                     warm: WarmStart, acceleration: Acceleration) -> tuple[np.ndarray, float]:
        x, size, _ = self._steps(x, loads, iterations, tolerance, warm, None, acceleration)
        if len(self._floor_violations(x)):
            repairs = acceleration if isinstance(acceleration, Anderson) else None
            x, _, _ = self._steps(x, loads, REPAIRS, tolerance, warm, np.zeros(0, dtype=int), repairs)
        return self.untangle(x), size

    def _steps(self, x: np.ndarray, loads: np.ndarray | None, iterations: int, tolerance: float,
               warm: WarmStart, active: np.ndarray | None,
               acceleration: Acceleration) -> tuple[np.ndarray, float, np.ndarray | None]:
        """Local/global steps from x, accelerated as `acceleration` says: the positions, the last step's
        size and the held set.

        active None: steps, at most `iterations`, until one moves no node by more than
        `tolerance`. Otherwise the floor repairs: steps holding elements over the volume floor
        (`step`'s `active`), until no element is under it or the steps converge; the history is
        restarted whenever the held set changes (the map iterated is another one), and the last
        iterate is always a step's own answer, never an extrapolation."""
        free = self.free
        memory = acceleration.memory if isinstance(acceleration, Anderson) else 0
        chebyshev = acceleration if isinstance(acceleration, Chebyshev) else None
        xs: list[np.ndarray] = []
        gs: list[np.ndarray] = []
        size = np.inf
        back, omega = x, 1.0  # Chebyshev: the iterate one step back, the last weight
        for k in range(iterations):
            gx, held = self.step(x, loads, warm, active)
            size = float(np.abs(gx - x).max(initial=0.0))
            if active is not None and held is not None and not np.array_equal(held, active):
                xs.clear()
                gs.clear()
            active = held
            if memory:
                xs.append(x[free].ravel())
                gs.append(gx[free].ravel())
                del xs[:-memory - 1], gs[:-memory - 1]
            x, current = gx, x
            if size <= tolerance or (active is not None and (k == iterations - 1 or not len(self._floor_violations(x)))):
                break
            if chebyshev is not None:
                omega = chebyshev.weight(k, omega)
                if omega != 1.0:
                    x = gx.copy()
                    x[free] = back[free] + omega * (gx[free] - back[free])
                back = current
            elif len(xs) > 1:
                res = np.stack(gs, axis=1) - np.stack(xs, axis=1)
                gamma = np.linalg.lstsq(np.diff(res, axis=1), res[:, -1], rcond=None)[0]
                x = gx.copy()
                x[free] = (gs[-1] - np.diff(np.stack(gs, axis=1), axis=1) @ gamma).reshape(-1, 3)
        return x, size, active
