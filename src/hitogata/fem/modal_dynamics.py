"""Exact time stepping of the decoupled modal equations and superposition u = Phi q.

Each mass-normalised mode obeys  q'' + c q' + lambda q = p(t),  with
c = alpha + beta lambda and p = phi^T f (eq. 4, corrected). Over a step of
length h with p linear in time (or constant), the solution is exact, so one
step is a fixed 2x2 linear map plus load terms,

    [q, q']_{n+1} = T [q, q']_n + g0 p_n + g1 p_{n+1},

computed for all modes at once. No step size is unstable or inaccurate for
any mode, under-, critically or over-damped.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as la

from hitogata.errors import HitogataError
from hitogata.fem.damping import modal_damping


@dataclass(frozen=True)
class ModalStep:
    """Exact one-step map for k modes and step ``dt``: transition (k, 2, 2), load terms (k, 2)."""

    dt: float
    transition: np.ndarray
    load_start: np.ndarray
    load_end: np.ndarray


def modal_step(eigenvalues: np.ndarray, alpha: float, beta: float, dt: float) -> ModalStep:
    """Exact step coefficients for q'' + (alpha + beta lambda) q' + lambda q = p, p linear over dt.

    The state [q, q', p, p_{n+1} - p_n] evolves by a constant 4x4 matrix Z
    (q' = q', q'' = -lambda q - c q' + p, p' = (p_{n+1} - p_n) / h), so the
    exact step is the matrix exponential exp(Z h), batched over modes. The
    free response it contains is e^{-ah}[[C + aS, S], [-lambda S, C - aS]]
    with a = c/2, w^2 = |lambda - a^2| and (C, S) = (cos wh, sin(wh)/w)
    under-damped, (1, h) critically damped, (cosh wh, sinh(wh)/w) over-damped
    (the tests check each against these closed forms). The exponential is used
    rather than those formulas because their load terms, (1 - e^{-ah}(C + aS)) /
    lambda and the like, lose digits to cancellation when the step is short
    against the slowest time constant (8e-6 relative for lambda = 1, h = 10 us),
    while scaling-and-squaring keeps every entry accurate (<= 3e-13 relative
    measured against extended-precision series, from 10 us steps to omega h = 170).
    """
    lam = np.asarray(eigenvalues, dtype=float)
    if not (np.isfinite(dt) and dt > 0.0):
        raise HitogataError(f"time step dt = {dt!r} is invalid; allowed: > 0 s")
    if not np.all(np.isfinite(lam)):
        raise HitogataError("eigenvalues contain NaN or infinity; allowed: finite values")
    c = modal_damping(lam, alpha, beta)
    h = float(dt)
    z = np.zeros((len(lam), 4, 4))
    z[:, 0, 1] = h
    z[:, 1, 0] = -lam * h
    z[:, 1, 1] = -c * h
    z[:, 1, 2] = h
    z[:, 2, 3] = 1.0
    e = la.expm(z) if len(lam) else z
    return ModalStep(h, e[:, :2, :2].copy(), e[:, :2, 2] - e[:, :2, 3], e[:, :2, 3].copy())


def advance(step: ModalStep, q: np.ndarray, qd: np.ndarray, p_start: np.ndarray,
            p_end: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """One exact step: modal displacements q and velocities qd (k,) or (k, m) -> after ``step.dt``.

    The modal load goes linearly from p_start to p_end (p_end None: held constant).
    """
    p_end = p_start if p_end is None else p_end
    t = step.transition
    g0, g1 = step.load_start, step.load_end
    if np.ndim(q) == 2:
        t = t[..., None]
        g0, g1 = g0[..., None], g1[..., None]
    q_new = t[:, 0, 0] * q + t[:, 0, 1] * qd + g0[:, 0] * p_start + g1[:, 0] * p_end
    qd_new = t[:, 1, 0] * q + t[:, 1, 1] * qd + g0[:, 1] * p_start + g1[:, 1] * p_end
    return q_new, qd_new


def integrate_modes(eigenvalues: np.ndarray, alpha: float, beta: float, dt: float, loads: np.ndarray,
                    q0: np.ndarray | None = None, qd0: np.ndarray | None = None,
                    hold: str = "linear") -> tuple[np.ndarray, np.ndarray]:
    """Modal response at t = 0, dt, ..., n dt to modal loads sampled at those times.

    loads: (n + 1, k) values of phi^T f at the step boundaries; ``hold``
    "linear" interpolates linearly in between, "constant" holds p_n over
    [t_n, t_{n+1}). Returns q and q' of shape (n + 1, k).
    """
    if hold not in ("linear", "constant"):
        raise HitogataError(f"load hold {hold!r} is unknown; allowed: 'linear' or 'constant'")
    lam = np.asarray(eigenvalues, dtype=float)
    loads = np.asarray(loads, dtype=float)
    if loads.ndim != 2 or loads.shape[1] != len(lam):
        raise HitogataError(f"modal loads have shape {loads.shape}; allowed: (steps + 1, {len(lam)})")
    step = modal_step(lam, alpha, beta, dt)
    q = np.zeros((len(loads), len(lam)))
    qd = np.zeros_like(q)
    q[0] = 0.0 if q0 is None else q0
    qd[0] = 0.0 if qd0 is None else qd0
    for n in range(len(loads) - 1):
        end = loads[n + 1] if hold == "linear" else None
        q[n + 1], qd[n + 1] = advance(step, q[n], qd[n], loads[n], end)
    return q, qd


def modal_loads(vectors: np.ndarray, forces: np.ndarray) -> np.ndarray:
    """Modal loads p = Phi^T f for nodal force vectors f (n_dofs,) or (steps, n_dofs)."""
    return np.asarray(forces) @ vectors


def superpose(vectors: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Displacements u = Phi q for modal coordinates q (k,) or (steps, k): (n_dofs,) or (steps, n_dofs)."""
    return np.asarray(q) @ vectors.T


def modal_energy(eigenvalues: np.ndarray, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """Kinetic plus strain energy (J) of mass-normalised modal states, summed over the last axis."""
    return 0.5 * np.sum(np.asarray(qd) ** 2 + np.asarray(eigenvalues) * np.asarray(q) ** 2, axis=-1)
