"""Direct time integration of M u'' + C u' + K u = f (eq. 3), as references for the modal path.

- ``newmark``: implicit Newmark, average acceleration by default (beta = 1/4,
  gamma = 1/2): unconditionally stable, second order, works on sparse
  matrices of any size with one factorization.
- ``exact_response``: the exact solution for loads linear between samples,
  from the matrix exponential of the first-order system. Dense, so for small
  meshes only; it has no time-discretisation error, which makes it the
  sharpest check of modal superposition.
Fixed nodes hold zero displacement in both.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp

from hitogata.errors import HitogataError
from hitogata.fem.dofs import free_dofs
from hitogata.fem.factor import factorize
from hitogata.options import FactorMethod


def newmark(M: sp.spmatrix, C: sp.spmatrix, K: sp.spmatrix, loads: np.ndarray, dt: float,
            u0: np.ndarray | None = None, v0: np.ndarray | None = None,
            fixed_nodes: np.ndarray | list[int] | None = None, beta: float = 0.25, gamma: float = 0.5,
            method: FactorMethod = "auto") -> tuple[np.ndarray, np.ndarray]:
    """Displacements and velocities (n + 1, n_dofs) at t = 0, dt, ..., for loads (n + 1, n_dofs) at those times."""
    free, (Mf, Cf, Kf), loads = _reduce(M, C, K, loads, dt, fixed_nodes)
    n_steps = len(loads)
    u = np.zeros((n_steps, len(free)))
    v = np.zeros_like(u)
    u[0] = 0.0 if u0 is None else np.asarray(u0)[free]
    v[0] = 0.0 if v0 is None else np.asarray(v0)[free]
    a = factorize(Mf, method, node_of_dof=free // 3)(loads[0] - Cf @ v[0] - Kf @ u[0])
    c0, c1 = 1.0 / (beta * dt * dt), gamma / (beta * dt)
    solve = factorize(Kf + c0 * Mf + c1 * Cf, method, node_of_dof=free // 3)
    for n in range(n_steps - 1):
        pred_u = u[n] + dt * v[n] + dt * dt * (0.5 - beta) * a
        pred_v = v[n] + dt * (1.0 - gamma) * a
        rhs = loads[n + 1] + Mf @ (c0 * pred_u) - Cf @ (pred_v - c1 * pred_u)
        u[n + 1] = solve(rhs)
        a = c0 * (u[n + 1] - pred_u)
        v[n + 1] = pred_v + gamma * dt * a
    return _expand(u, free, K.shape[0]), _expand(v, free, K.shape[0])


def exact_response(M: sp.spmatrix, C: sp.spmatrix, K: sp.spmatrix, loads: np.ndarray, dt: float,
                   u0: np.ndarray | None = None, v0: np.ndarray | None = None,
                   fixed_nodes: np.ndarray | list[int] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Exact displacements and velocities (n + 1, n_dofs) for loads varying linearly between samples.

    State z = [u, u'] obeys z' = A z + B f with A = [[0, I], [-M^-1 K, -M^-1 C]].
    Appending f and its per-step increment to the state makes the system
    autonomous, so one matrix exponential of size 2 n_free + 2 n_free gives
    the exact step map (dense: keep n_free below ~500).
    """
    free, (Mf, Cf, Kf), loads = _reduce(M, C, K, loads, dt, fixed_nodes)
    n = len(free)
    minv = la.inv(Mf.toarray())
    z = np.zeros((4 * n, 4 * n))
    z[:n, n:2 * n] = np.eye(n)
    z[n:2 * n, :n] = -minv @ Kf.toarray()
    z[n:2 * n, n:2 * n] = -minv @ Cf.toarray()
    z[n:2 * n, 2 * n:3 * n] = minv
    z[2 * n:3 * n, 3 * n:] = np.eye(n) / dt
    step = la.expm(z * dt)
    t_state, t_load, t_slope = step[:2 * n, :2 * n], step[:2 * n, 2 * n:3 * n], step[:2 * n, 3 * n:]
    states = np.zeros((len(loads), 2 * n))
    states[0, :n] = 0.0 if u0 is None else np.asarray(u0)[free]
    states[0, n:] = 0.0 if v0 is None else np.asarray(v0)[free]
    for k in range(len(loads) - 1):
        states[k + 1] = t_state @ states[k] + t_load @ loads[k] + t_slope @ (loads[k + 1] - loads[k])
    return _expand(states[:, :n], free, K.shape[0]), _expand(states[:, n:], free, K.shape[0])


def _reduce(M: sp.spmatrix, C: sp.spmatrix, K: sp.spmatrix, loads: np.ndarray, dt: float,
            fixed_nodes: np.ndarray | list[int] | None) -> tuple[np.ndarray, tuple, np.ndarray]:
    """Free dofs, (M, C, K) restricted to them, and the loads on them."""
    if not (np.isfinite(dt) and dt > 0.0):
        raise HitogataError(f"time step dt = {dt!r} is invalid; allowed: > 0 s")
    loads = np.asarray(loads, dtype=float)
    if loads.ndim != 2 or loads.shape[1] != K.shape[0]:
        raise HitogataError(f"loads have shape {loads.shape}; allowed: (steps + 1, {K.shape[0]})")
    free = free_dofs(K.shape[0], fixed_nodes)
    mats = tuple(sp.csr_matrix(X)[free][:, free] for X in (M, C, K))
    return free, mats, loads[:, free]


def _expand(values: np.ndarray, free: np.ndarray, n_dofs: int) -> np.ndarray:
    """Free-dof histories (steps, n_free) to full size with zeros on fixed dofs."""
    full = np.zeros((len(values), n_dofs))
    full[:, free] = values
    return full
