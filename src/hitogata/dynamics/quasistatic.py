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
(one more back-substitution per region). The steps are Anderson-accelerated
and start from the previous frame's answer, so a few per frame suffice.

Elements kept right side out (a floor, not a guarantee): after the
accelerated steps, while some element's corner volume is below FLOOR x its
rest volume, up to REPAIRS plain steps add those elements' volumes as
further multipliers (an inequality: one the floor would pull down is let
go), each projection capped at STEP_CAP per node (a flat element's
linearisation is poor), then the regions' volumes restored exactly. The
few elements that deep creases leave below the floor after that are lifted
by moving single nodes (`untangle`). A pose with no such element costs two
volume checks more than before.

The solve runs on the elements' corner (linear) mesh: the correction is
smooth, the shear-only energy does not lock, and it is ~10x cheaper than on
the quadratic mesh; the dynamics lift it to the mid-edge nodes.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from hitogata.dynamics.rotations import extract_rotations
from hitogata.dynamics.untangle import Untangler
from hitogata.fem.elements import element_order, quadrature, shape_gradients, tet_geometry
from hitogata.geometry.tets import TET_FACES, signed_volumes
from hitogata.fem.factor import factorize
from hitogata.fem.materials import lame, per_element

MEMORY = 5  # Anderson acceleration: past steps mixed
REPAIRS = 30  # at most so many plain steps after the last one, holding elements over the floor
STEP_CAP = 0.02  # m: the largest node move of one projection while elements are held over the floor
FLOOR = 0.02  # an element's corner volume is held at least at this share of its rest volume


def rotate(rotations: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """R v row by row: rotations (..., 3, 3), vectors (..., 3)."""
    return np.einsum("...ij,...j->...i", rotations, vectors)


def unrotate(rotations: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """Rᵀ v row by row."""
    return np.einsum("...ji,...j->...i", rotations, vectors)


class QuasiStatic:
    """Local/global solver of the tissue's equilibrium about a posed skeleton (see the module note)."""

    def __init__(self, points: np.ndarray, elements: np.ndarray, E: np.ndarray | float, nu: np.ndarray | float,
                 fixed_nodes: np.ndarray, region: np.ndarray, constrained_regions: tuple[int, ...],
                 method: str = "auto") -> None:
        self.points = np.asarray(points, dtype=float)
        self.elements = np.asarray(elements)
        self.region = np.asarray(region)
        self.constrained = tuple(int(r) for r in constrained_regions)
        n, t = len(self.points), len(self.elements)
        order = element_order(self.elements)
        bary, w = quadrature(2 * (order - 1))
        grads_l, vol = tet_geometry(self.points, self.elements)
        self.grads = shape_gradients(order, bary, grads_l)  # (T, Q, n, 3)
        _, mu = lame(per_element(t, E, "E"), per_element(t, nu, "nu"))
        self.weights = (w[None, :] * vol[:, None]) * mu[:, None]  # (T, Q): w V mu
        a = np.einsum("tq,tqai,tqbi->tab", self.weights, self.grads, self.grads, optimize=True)
        rows = np.repeat(self.elements, self.elements.shape[1], axis=1).ravel()
        cols = np.tile(self.elements, (1, self.elements.shape[1])).ravel()
        lap = sp.csr_matrix((a.ravel(), (rows, cols)), shape=(n, n))
        mask = np.ones(n, dtype=bool)
        mask[np.asarray(fixed_nodes)] = False
        self.free, self.fixed = np.flatnonzero(mask), np.asarray(fixed_nodes)
        self._lap_fb = lap[self.free][:, self.fixed]
        self._solve = factorize(lap[self.free][:, self.free], method)
        self.rest_volumes = self.region_volumes(self.points)
        self.rest_element_volumes = corner_volumes(self.points, self.elements)
        # elements with a free corner: those whose volume the floor can hold
        self._movable = np.isin(self.elements[:, :4], self.free).any(axis=1)
        self.active = np.zeros(0, dtype=int)  # elements held at the volume floor in the current solve
        self.floor = False  # whether steps add elements under the floor to the active ones
        self.untangle = Untangler(self.points, self.elements, mask, FLOOR)
        self.quaternions = np.tile([1.0, 0.0, 0.0, 0.0], (t * len(w), 1))  # warm start of the local step

    def region_volumes(self, x: np.ndarray) -> np.ndarray:
        """Volume (m³) of each constrained region at node positions x (corner tets)."""
        v = corner_volumes(x, self.elements)
        return np.array([v[self.region == r].sum() for r in self.constrained])

    def _volume_gradients(self, x: np.ndarray) -> np.ndarray:
        """(regions, N, 3): derivative of each constrained region's volume by the node positions."""
        c = x[self.elements[:, :4]]
        g = np.empty(c.shape)
        for a, (i, j, k) in enumerate(TET_FACES):
            g[:, a] = -np.cross(c[:, j] - c[:, i], c[:, k] - c[:, i]) / 6.0
        out = np.zeros((len(self.constrained), len(x), 3))
        for m, r in enumerate(self.constrained):
            mine = self.region == r
            ids = self.elements[mine, :4].ravel()
            for axis in range(3):
                out[m, :, axis] = np.bincount(ids, g[mine][..., axis].ravel(), minlength=len(x))
        return out

    def _global(self, rhs: np.ndarray, bones: np.ndarray | None) -> np.ndarray:
        """Free-node values solving L x = rhs with the bone nodes at `bones` (None: zero)."""
        b = rhs[self.free]
        if bones is not None:
            b = b - self._lap_fb @ bones
        return self._solve(np.ascontiguousarray(b))

    def step(self, x: np.ndarray, loads: np.ndarray | None) -> np.ndarray:
        """One local/global iteration from node positions x (N, 3); bone nodes keep their positions."""
        F = np.einsum("tnj,tqni->tqji", x[self.elements], self.grads, optimize=True)
        R, self.quaternions = extract_rotations(F.reshape(-1, 3, 3), self.quaternions)
        R = R.reshape(F.shape)
        per_node = np.einsum("tq,tqji,tqni->tnj", self.weights, R, self.grads, optimize=True)
        rhs = np.empty((len(x), 3))
        flat = self.elements.ravel()
        for axis in range(3):
            rhs[:, axis] = np.bincount(flat, per_node[..., axis].ravel(), minlength=len(x))
        if loads is not None:
            rhs += 0.5 * loads
        new = x.copy()
        new[self.free] = self._global(rhs, x[self.fixed])
        return self._project(new)

    def _floor_violations(self, x: np.ndarray) -> np.ndarray:
        """Movable elements whose corner volume at x is below the floor."""
        v = corner_volumes(x, self.elements)
        return np.flatnonzero((v < FLOOR * self.rest_element_volumes) & self._movable)

    def _project(self, new: np.ndarray) -> np.ndarray:
        """Enforce the linearised constraints at `new`: each region's rest volume, and the volume
        floor of the active elements (those that have fallen below it in this solve), by one
        multiplier each (a pressure), the Laplacian's response solved by back-substitution."""
        if self.floor:
            self.active = np.union1d(self.active, self._floor_violations(new))
        if not self.constrained and not len(self.active):
            return new
        grads = [self._volume_gradients(new)] if self.constrained else []
        targets = [self.rest_volumes - self.region_volumes(new)] if self.constrained else []
        if len(self.active):
            grads.append(self._element_volume_gradients(new, self.active))
            targets.append(FLOOR * self.rest_element_volumes[self.active]
                           - corner_volumes(new, self.elements[self.active]))
        grads = np.concatenate(grads)  # (constraints, N, 3)
        g_free = grads[:, self.free]
        m = len(grads)
        # L⁻¹ g, all constraints and axes in one back-substitution: (constraints, free, 3)
        basis = self._solve(np.ascontiguousarray(g_free.transpose(1, 2, 0).reshape(len(self.free), 3 * m)))
        basis = basis.reshape(len(self.free), 3, m).transpose(2, 0, 1)
        coupling = np.einsum("rfk,sfk->rs", g_free, basis)
        p = np.linalg.lstsq(coupling, np.concatenate(targets), rcond=1e-12)[0]
        move = np.einsum("r,rfk->fk", p, basis)
        if len(self.active):  # the floor is an inequality: an element it would pull down is let go
            self.active = self.active[p[m - len(self.active):] >= 0.0]
        new = new.copy()
        if len(self.active):  # a flat element's linearisation is poor: no node moves more than STEP_CAP,
            move *= min(1.0, STEP_CAP / max(float(np.abs(move).max()), 1e-30))
            new[self.free] += move
            if self.constrained:  # and the regions' volumes are then restored exactly
                grads = self._volume_gradients(new)
                basis = np.stack([self._global(gr, None) for gr in grads])
                coupling = np.einsum("rfk,sfk->rs", grads[:, self.free], basis)
                p = np.linalg.solve(coupling, self.rest_volumes - self.region_volumes(new))
                new[self.free] += np.einsum("r,rfk->fk", p, basis)
            return new
        new[self.free] += move
        return new

    def _element_volume_gradients(self, x: np.ndarray, elements: np.ndarray) -> np.ndarray:
        """(len(elements), N, 3): derivative of each listed element's corner volume by the node positions."""
        corners = self.elements[elements, :4]
        c = x[corners]
        out = np.zeros((len(elements), len(x), 3))
        rows = np.arange(len(elements))
        for a, (i, j, k) in enumerate(TET_FACES):
            out[rows, corners[:, a]] += -np.cross(c[:, j] - c[:, i], c[:, k] - c[:, i]) / 6.0
        return out

    def solve(self, x: np.ndarray, loads: np.ndarray | None = None, iterations: int = 8,
              tolerance: float = 1e-5) -> tuple[np.ndarray, float]:
        """Node positions (N, 3) after at most `iterations` steps from x, and the last step's size (m).

        Anderson acceleration (Walker & Ni 2011; for local/global solvers Peng
        et al. 2018) mixes the last `MEMORY` steps by least squares: the
        slow, bending-like error fields that plain local/global steps shrink
        by a few per cent per step fall several times faster. Stops early
        when a step moves no node by more than `tolerance`.
        """
        free = self.free
        xs, gs = [], []
        size = np.inf
        self.active = np.zeros(0, dtype=int)
        for _ in range(iterations):
            gx = self.step(x, loads)
            size = float(np.abs(gx - x).max(initial=0.0))
            xs.append(x[free].ravel())
            gs.append(gx[free].ravel())
            del xs[:-MEMORY - 1], gs[:-MEMORY - 1]
            x = gx
            if size <= tolerance:
                break
            if len(xs) > 1:
                res = np.stack(gs, axis=1) - np.stack(xs, axis=1)
                gamma = np.linalg.lstsq(np.diff(res, axis=1), res[:, -1], rcond=None)[0]
                x = gx.copy()
                x[free] = (gs[-1] - np.diff(np.stack(gs, axis=1), axis=1) @ gamma).reshape(-1, 3)
        self.floor = True
        for _ in range(REPAIRS):
            if not len(self._floor_violations(x)):
                break
            x = self.step(x, loads)
        self.floor = False
        return self.untangle(x), size


def corner_volumes(x: np.ndarray, elements: np.ndarray) -> np.ndarray:
    """Signed volume (T,) of each element's corner tetrahedron."""
    return signed_volumes(x, elements[:, :4])
