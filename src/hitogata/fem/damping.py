"""Rayleigh damping C = alpha M + beta K and what it means mode by mode.

Erratum to the paper: with mass-normalised modes (Phi^T M Phi = I,
Phi^T K Phi = diag(lambda)), Phi^T C Phi = alpha I + beta diag(lambda), so
mode i sees the scalar damping c_i = alpha + beta lambda_i (not the paper's
"alpha I + beta K") and the damping ratio zeta_i = c_i / (2 omega_i) =
alpha / (2 omega_i) + beta omega_i / 2.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from hitogata.errors import HitogataError


def check_rayleigh(alpha: float, beta: float) -> None:
    """Raise HitogataError unless alpha >= 0 (1/s) and beta >= 0 (s), both finite."""
    for name, value, unit in (("alpha", alpha, "1/s"), ("beta", beta, "s")):
        if not (np.isfinite(value) and value >= 0.0):
            raise HitogataError(f"Rayleigh {name} = {value!r} is invalid; allowed: a finite value >= 0 {unit}")


def rayleigh_coefficients(zeta1: float, f1: float, zeta2: float, f2: float) -> tuple[float, float]:
    """(alpha, beta) giving damping ratio zeta1 at f1 Hz and zeta2 at f2 Hz.

    Solves zeta(omega) = alpha / (2 omega) + beta omega / 2 at both points.
    Refuses targets that would need a negative alpha or beta (the ratio would
    turn negative, i.e. energy would be created, at some frequency).
    """
    for name, value in (("f1", f1), ("f2", f2)):
        if not (np.isfinite(value) and value > 0.0):
            raise HitogataError(f"damping target frequency {name} = {value!r} is invalid; allowed: > 0 Hz")
    for name, value in (("zeta1", zeta1), ("zeta2", zeta2)):
        if not (np.isfinite(value) and value >= 0.0):
            raise HitogataError(f"damping ratio {name} = {value!r} is invalid; allowed: >= 0")
    if f1 == f2:
        raise HitogataError(f"damping target frequencies are equal ({f1!r} Hz); allowed: two different frequencies")
    w1, w2 = 2.0 * np.pi * f1, 2.0 * np.pi * f2
    den = w2**2 - w1**2
    alpha = 2.0 * w1 * w2 * (zeta1 * w2 - zeta2 * w1) / den
    beta = 2.0 * (zeta2 * w2 - zeta1 * w1) / den
    if alpha < 0.0 or beta < 0.0:
        raise HitogataError(
            f"damping ratios {zeta1!r} at {f1!r} Hz and {zeta2!r} at {f2!r} Hz need alpha = {alpha:.3g}, "
            f"beta = {beta:.3g}; allowed: targets giving alpha >= 0 and beta >= 0 "
            "(zeta2/zeta1 between f1/f2 and f2/f1)"
        )
    return float(alpha), float(beta)


def modal_damping(eigenvalues: np.ndarray, alpha: float, beta: float) -> np.ndarray:
    """Modal damping coefficients c_i = alpha + beta lambda_i (1/s) of mass-normalised modes."""
    check_rayleigh(alpha, beta)
    return alpha + beta * np.asarray(eigenvalues, dtype=float)


def damping_ratios(eigenvalues: np.ndarray, alpha: float, beta: float) -> np.ndarray:
    """Damping ratios zeta_i = (alpha + beta lambda_i) / (2 sqrt(lambda_i)); 1 is critical."""
    lam = np.asarray(eigenvalues, dtype=float)
    return modal_damping(lam, alpha, beta) / (2.0 * np.sqrt(lam))


def damping_matrix(K: sp.spmatrix, M: sp.spmatrix, alpha: float, beta: float) -> sp.csr_matrix:
    """C = alpha M + beta K, for direct time integration of M u'' + C u' + K u = f."""
    check_rayleigh(alpha, beta)
    return sp.csr_matrix(alpha * M + beta * K)
