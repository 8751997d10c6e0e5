"""Last-resort untangling: move the free nodes round flat or inverted elements until none is left.

The quasi-statics' volume floor pulls most elements back right side out, but
in deep creases (thigh against belly at 120° of hip flexion, calf against
thigh at 130° of knee flexion) a few elements next to the bones can stay
flat or inverted: the floor's multipliers act through the whole Laplacian
and fight the bones held nearby. What is left is a local problem.

An element's volume is linear in any one of its corners, so the volume
deficit of the elements round the offending nodes, linearised in those
nodes' moves, is a linear programme (after Freitag & Plassmann 2000,
"Local optimization-based simplicial mesh untangling and improvement",
IJNME 49:109, there node by node; here all the nodes of a crease at once,
since two flat elements sharing a node can each need it on the other's side):
maximise Σ_t s_t + W Σ_t min(s_t, 0) subject to v_t + Σ_k g_tk·d_k ≥ s_t V_t,
s_t ≤ floor (inverted volume weighs W times more), a
small price on Σ|d| so that nodes move no further than they must, and a
trust region |d| ≤ r. A step that does not lower the true deficit
Σ max(0, floor − v_t / V_t) + W Σ max(0, −v_t / V_t) halves r (sequential
linear programming).

Moving all the nodes of a crease at once, the programme's linearised volumes
miss the true ones by the products of two corners' moves, and it can stall
with an element a fraction of a per cent inside out (the female's seated
90/90 pose: two viscera elements at −0.07 % and −1e-12 of their rest
volume). What the programmes leave inverted is then taken by a smooth
penalty on the true volumes, Σ (floor − v/V)₊² + W' Σ (−v/V)₊², plus a
small price on the moves, minimised by L-BFGS to convergence over the
nodes round the elements under the floor and one ring more
(docs/decisions/0061-a-held-posture-that-converges.md).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linprog, minimize

from hitogata.dynamics.volumes import corner_gradients, corner_volumes, volumes_and_gradients

STEPS = 20  # at most so many linear programmes (accepted or not)
REACH = 0.25  # first trust radius, as a share of the mean edge length round the moved nodes
# Volume below zero costs this much more than volume below the floor: with equal weights, lifting
# an inverted element by flattening its neighbours as much was no gain, and the programme stalled
# with it inverted (whole-body hip flexion 120° after a knee pose: one element at -0.2 % of rest).
INVERSION_WEIGHT = 10.0
ROUND_OFF = 1e-9  # volume ratios this close to the floor count as on it
MOVE_PRICE = 0.05  # per metre of movement (L1), against volume ratios of order FLOOR
# The smooth pass over what the programmes leave inverted: an inverted element's squared shortfall weighs this
# much more than one under the floor (at 10 the female seated pose kept one element at −0.08 %), the moves cost
# PULL x (move / mean edge length)², and L-BFGS takes at most SMOOTH_ITERATIONS (the female seated pose 1,300-1,500).
SMOOTH_WEIGHT = 100.0
PULL = 1e-4
SMOOTH_ITERATIONS = 3000


class Untangler:
    """Repair of the elements whose corner volume falls below `floor` x rest, by moving their free corners."""

    def __init__(self, rest: np.ndarray, elements: np.ndarray, movable: np.ndarray, floor: float) -> None:
        self.corners = np.asarray(elements)[:, :4]
        self.rest_volumes = corner_volumes(rest, self.corners)
        self.movable = np.asarray(movable, dtype=bool)  # (N,): nodes the untangler may move
        self.floor = float(floor)
        edges = rest[self.corners[:, [1, 2, 3, 2, 3, 3]]] - rest[self.corners[:, [0, 0, 0, 1, 1, 2]]]
        self._element_size = np.linalg.norm(edges, axis=2).mean(axis=1)

    def below_floor(self, x: np.ndarray) -> np.ndarray:
        """Elements with a movable corner whose corner volume at x is below the floor (beyond round-off:
        the linear programmes leave elements exactly at it)."""
        low = corner_volumes(x, self.corners) < (self.floor - ROUND_OFF) * self.rest_volumes
        return np.flatnonzero(low & self.movable[self.corners].any(axis=1))

    def deficit(self, x: np.ndarray, elements: np.ndarray) -> float:
        """Σ max(0, floor − v/V) + W Σ max(0, −v/V) over the listed elements: an inverted element
        weighs more than a flat one, so lifting it is worth flattening a neighbour a little. Shortfalls
        within ROUND_OFF of the floor do not count (as in `below_floor`): a programme that lifts an
        element onto the floor leaves ~1e-16 of one, and chasing it cost 19 more programmes (0.06 s)."""
        ratio = corner_volumes(x, self.corners[elements]) / self.rest_volumes[elements]
        short = self.floor - ratio
        return float(np.where(short > ROUND_OFF, short, 0.0).sum() + INVERSION_WEIGHT * np.maximum(-ratio, 0.0).sum())

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """Node positions (N, 3) with the elements below the floor lifted as far as the free nodes allow."""
        x = np.array(x, dtype=float)
        bad = self.below_floor(x)
        if not len(bad):
            return x
        nodes = np.unique(self.corners[bad])
        nodes = nodes[self.movable[nodes]]
        elements = np.flatnonzero(np.isin(self.corners, nodes).any(axis=1))
        reach = REACH * float(self._element_size[bad].mean())
        deficit = self.deficit(x, elements)
        for _ in range(STEPS):
            if deficit <= 0.0:
                break
            trial = x.copy()
            trial[nodes] += self._step(x, nodes, elements, reach)
            now = self.deficit(trial, elements)
            if now < deficit:
                x, deficit = trial, now
            else:
                reach *= 0.5
        return self._smooth(x)

    def _smooth(self, x: np.ndarray) -> np.ndarray:
        """x with the elements left inverted lifted by the smooth penalty (module note), or as it was
        where none is."""
        if not (corner_volumes(x, self.corners) <= 0.0).any():
            return x
        nodes = np.unique(self.corners[self.below_floor(x)])
        nodes = np.unique(self.corners[np.isin(self.corners, nodes[self.movable[nodes]]).any(axis=1)])
        nodes = nodes[self.movable[nodes]]
        if not len(nodes):  # what is inverted has no free corner
            return x
        elements = np.flatnonzero(np.isin(self.corners, nodes).any(axis=1))
        corners, rest = self.corners[elements], self.rest_volumes[elements]
        column = np.full(len(x), -1)
        column[nodes] = np.arange(len(nodes))
        local = column[corners]  # (m, 4): -1 where a corner stays
        held = local >= 0
        scale = PULL / float(self._element_size[elements].mean()) ** 2
        start = x[nodes].copy()

        def energy(z: np.ndarray) -> tuple[float, np.ndarray]:
            y = x.copy()
            y[nodes] = z.reshape(-1, 3)
            volumes, gradients = volumes_and_gradients(y, corners)  # (m,), (3, 4, m)
            ratio = volumes / rest
            under, inside = np.maximum(self.floor - ratio, 0.0), np.maximum(-ratio, 0.0)
            slope = -2.0 * (under + SMOOTH_WEIGHT * inside) / rest  # dE/dv
            grad = np.zeros((len(nodes), 3))
            for axis in range(3):
                grad[:, axis] = np.bincount(local[held], (gradients[axis].T * slope[:, None])[held],
                                            minlength=len(nodes))
            move = z.reshape(-1, 3) - start
            value = float((under**2).sum() + SMOOTH_WEIGHT * (inside**2).sum() + scale * (move**2).sum())
            return value, (grad + 2.0 * scale * move).ravel()

        result = minimize(energy, start.ravel(), jac=True, method="L-BFGS-B",
                          options={"maxiter": SMOOTH_ITERATIONS, "gtol": 1e-10, "ftol": 1e-12})
        out = x.copy()
        out[nodes] = result.x.reshape(-1, 3)
        return out

    def _step(self, x: np.ndarray, nodes: np.ndarray, elements: np.ndarray, reach: float) -> np.ndarray:
        """Moves (len(nodes), 3) solving the linearised programme within the trust radius."""
        n, m = len(nodes), len(elements)
        corners = self.corners[elements]
        gradients = corner_gradients(x, corners)  # (3, 4, m): dv/dx of each corner
        column = np.full(len(x), -1)
        column[nodes] = np.arange(n)
        rows, cols, values = [], [], []
        for a in range(4):
            moved = np.flatnonzero(column[corners[:, a]] >= 0)
            for axis in range(3):
                rows.append(moved)
                cols.append(3 * column[corners[moved, a]] + axis)
                values.append(-gradients[axis, a, moved])
        # variables: d (3n), |d| (3n), s (m), t = min(s, 0) (m); minimise -Σ s - W Σ t + price Σ|d|
        volume = sp.csr_matrix((np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))), shape=(m, 3 * n))
        eye, zero_m = sp.identity(3 * n, format="csr"), sp.csr_matrix((m, m))
        a_ub = sp.vstack([
            sp.hstack([volume, sp.csr_matrix((m, 3 * n)), sp.diags(self.rest_volumes[elements]), zero_m]),
            sp.hstack([eye, -eye, sp.csr_matrix((3 * n, 2 * m))]),
            sp.hstack([-eye, -eye, sp.csr_matrix((3 * n, 2 * m))]),
            sp.hstack([sp.csr_matrix((m, 6 * n)), -sp.identity(m), sp.identity(m)]),
        ], format="csr")
        b_ub = np.r_[corner_volumes(x, corners), np.zeros(6 * n + m)]
        cost = np.r_[np.zeros(3 * n), np.full(3 * n, MOVE_PRICE), -np.ones(m), np.full(m, -INVERSION_WEIGHT)]
        bounds = ([(-reach, reach)] * (3 * n) + [(0.0, reach)] * (3 * n) + [(None, self.floor)] * m
                  + [(None, 0.0)] * m)
        result = linprog(cost, A_ub=a_ub, b_ub=b_ub, bounds=bounds, method="highs")
        if result.status != 0:
            return np.zeros((n, 3))
        return result.x[:3 * n].reshape(n, 3)
