"""Modal dynamics (eq. 3-4): superposition vs direct integration, Rayleigh damping, exact modal steps."""

import numpy as np
import pytest

from hitogata.errors import HitogataError
from hitogata.fem.assembly import mass_matrix, stiffness_matrix
from hitogata.fem.verify.box_mesh import box_mesh
from hitogata.fem.damping import damping_matrix, damping_ratios, modal_damping, rayleigh_coefficients
from hitogata.fem.verify.direct import exact_response, newmark
from hitogata.fem.elements import lift_node_set, p2_mesh
from hitogata.fem.loads import nodal_load
from hitogata.fem.modal_dynamics import (
    advance,
    integrate_modes,
    modal_energy,
    modal_loads,
    modal_step,
    superpose,
)
from hitogata.fem.modes import solve_modes


@pytest.fixture(scope="module")
def beam():
    """A small clamped P2 cantilever (1 x 0.1 x 0.1 m, 2 x 1 x 1 cells): 108 free dofs, all modes."""
    points, tets = box_mesh((1.0, 0.1, 0.1), (2, 1, 1))
    fixed = np.flatnonzero(points[:, 0] < 1e-12)
    points, tets = p2_mesh(points, tets)
    fixed = lift_node_set(tets, fixed)
    K = stiffness_matrix(points, tets, 1e6, 0.3)
    M = mass_matrix(points, tets, 1000.0)
    n_free = K.shape[0] - 3 * len(fixed)
    modes = solve_modes(K, M, n_free, fixed, solver="dense")
    tip = np.flatnonzero(points[:, 0] > 1.0 - 1e-9)
    return dict(points=points, K=K, M=M, fixed=fixed, modes=modes, tip=tip)


def tip_loads(beam, dt, duration):
    """A 1 N total downward (-Y) tip force ramped up over 0.5 s then held, sampled every dt."""
    t = np.arange(int(round(duration / dt)) + 1) * dt
    unit = nodal_load(len(beam["points"]), beam["tip"], (0.0, -1.0 / len(beam["tip"]), 0.0))
    return np.minimum(t / 0.5, 1.0)[:, None] * unit


def test_modal_superposition_with_all_modes_equals_direct_integration(beam):
    K, M, fixed, modes = beam["K"], beam["M"], beam["fixed"], beam["modes"]
    f1 = modes.frequencies[0]
    alpha, beta = rayleigh_coefficients(0.05, f1, 0.05, 10 * f1)
    C = damping_matrix(K, M, alpha, beta)
    phi = modes.vectors
    # the erratum: modal damping is diag(alpha + beta lambda), not "alpha I + beta K"
    assert np.allclose(phi.T @ C @ phi, np.diag(modal_damping(modes.eigenvalues, alpha, beta)),
                       atol=1e-9 * modes.eigenvalues.max() * beta)

    dt, duration = 0.01, 3.0
    f = tip_loads(beam, dt, duration)
    u_direct, v_direct = exact_response(M, C, K, f, dt, fixed_nodes=fixed)
    q, qd = integrate_modes(modes.eigenvalues, alpha, beta, dt, modal_loads(phi, f))
    u_modal, v_modal = superpose(phi, q), superpose(phi, qd)
    err = np.abs(u_modal - u_direct).max() / np.abs(u_direct).max()
    err_v = np.abs(v_modal - v_direct).max() / np.abs(v_direct).max()
    print(f"all {phi.shape[1]} modes vs exact direct integration: displacement {err:.1e}, velocity {err_v:.1e}")
    assert err < 1e-6 and err_v < 1e-6

    tip_y = 3 * beam["tip"] + 1
    reference = u_direct[:, tip_y].mean(axis=1)
    print("truncation error of the tip deflection (max over 3 s, relative to its peak):")
    errors = []
    for k in (2, 4, 6, 10, 20, 40):
        qk, _ = integrate_modes(modes.eigenvalues[:k], alpha, beta, dt, modal_loads(phi[:, :k], f))
        tip = superpose(phi[:, :k], qk)[:, tip_y].mean(axis=1)
        errors.append(np.abs(tip - reference).max() / np.abs(reference).max())
        print(f"  {k:3d} modes: {errors[-1]:.2e}")
    # the two first bending modes (y and z, skewed by the mesh) carry nearly all of a tip load's response
    assert errors[0] < 0.05
    assert errors[-1] < errors[0] / 10


def test_newmark_converges_at_second_order_to_modal_superposition(beam):
    """Direct implicit integration (Newmark, average acceleration) of eq. 3 against all modes superposed."""
    K, M, fixed, modes = beam["K"], beam["M"], beam["fixed"], beam["modes"]
    f1 = modes.frequencies[0]
    alpha, beta = rayleigh_coefficients(0.05, f1, 0.05, 10 * f1)
    C = damping_matrix(K, M, alpha, beta)
    dt, duration = 0.02, 2.0
    f = tip_loads(beam, dt, duration)
    q, _ = integrate_modes(modes.eigenvalues, alpha, beta, dt, modal_loads(modes.vectors, f))
    u_modal = superpose(modes.vectors, q)
    errors = []
    for refine in (1, 2, 4, 64):
        h = dt / refine
        u, _ = newmark(M, C, K, tip_loads(beam, h, duration), h, fixed_nodes=fixed)
        errors.append(np.abs(u[::refine] - u_modal).max() / np.abs(u_modal).max())
    print("Newmark vs all-mode superposition, dt = 20, 10, 5, 0.31 ms: " + ", ".join(f"{e:.2e}" for e in errors))
    assert errors[0] / errors[1] == pytest.approx(4.0, rel=0.1)
    assert errors[1] / errors[2] == pytest.approx(4.0, rel=0.1)
    assert errors[3] < 1e-6


def test_single_mode_decays_as_exp_minus_zeta_omega_t(beam):
    K, M, fixed, modes = beam["K"], beam["M"], beam["fixed"], beam["modes"]
    f1, f2 = modes.frequencies[0], modes.frequencies[4]
    alpha, beta = rayleigh_coefficients(0.03, f1, 0.03, f2)
    zeta = damping_ratios(modes.eigenvalues[:1], alpha, beta)[0]
    assert zeta == pytest.approx(0.03, rel=1e-12)
    omega = np.sqrt(modes.eigenvalues[0])
    omega_d = omega * np.sqrt(1 - zeta**2)
    dt, n = 0.005, 2000
    t = np.arange(n + 1) * dt
    expected = np.exp(-zeta * omega * t) * (np.cos(omega_d * t) + zeta / np.sqrt(1 - zeta**2) * np.sin(omega_d * t))

    # modal path: mode 1 released from q = 1 at rest
    q, _ = integrate_modes(modes.eigenvalues[:1], alpha, beta, dt, np.zeros((n + 1, 1)), q0=np.ones(1))
    assert np.abs(q[:, 0] - expected).max() < 1e-10

    # physical path, no modes involved: release the body from the shape of mode 1 under C = alpha M + beta K
    C = damping_matrix(K, M, alpha, beta)
    u, _ = exact_response(M, C, K, np.zeros((401, K.shape[0])), dt, u0=modes.vectors[:, 0], fixed_nodes=fixed)
    q_direct = u @ (M @ modes.vectors[:, 0])
    assert np.abs(q_direct - expected[:401]).max() < 1e-8
    peaks = [i for i in range(1, n) if q[i, 0] > q[i - 1, 0] and q[i, 0] > q[i + 1, 0]]
    decrement = np.log(q[peaks[0], 0] / q[peaks[4], 0]) / 4
    assert decrement == pytest.approx(2 * np.pi * zeta / np.sqrt(1 - zeta**2), rel=1e-3)


def test_undamped_modal_integration_conserves_energy_over_ten_seconds(beam):
    lam = beam["modes"].eigenvalues  # 0.5 Hz .. ~2 kHz: most periods far shorter than the step
    rng = np.random.default_rng(1)
    q0 = rng.standard_normal(len(lam)) / np.sqrt(lam)
    qd0 = rng.standard_normal(len(lam))
    for dt in (0.01, 0.37):
        n = int(round(10.0 / dt))
        q, qd = integrate_modes(lam, 0.0, 0.0, dt, np.zeros((n + 1, len(lam))), q0, qd0)
        energy = modal_energy(lam, q, qd)
        drift = np.abs(energy / energy[0] - 1).max()
        print(f"dt = {dt} s: max relative energy drift over 10 s {drift:.1e}")
        assert drift < 1e-6


def closed_form(lam, c, q0, v0, p0, rate, t):
    """q(t) for q'' + c q' + lam q = p0 + rate t, by damping regime, from hand-derived formulas."""
    a = c / 2
    # particular solution (p0 + rate t) / lam - c rate / lam^2, and the deviation from it at t = 0
    qp = (p0 + rate * t) / lam - c * rate / lam**2
    x0 = q0 - (p0 / lam - c * rate / lam**2)
    y0 = v0 - rate / lam
    if c * c < 4 * lam:
        w = np.sqrt(lam - a * a)
        return qp + np.exp(-a * t) * (x0 * np.cos(w * t) + (y0 + a * x0) / w * np.sin(w * t))
    if c * c == 4 * lam:
        return qp + np.exp(-a * t) * (x0 + (y0 + a * x0) * t)
    w = np.sqrt(a * a - lam)
    r1, r2 = -a + w, -a - w
    c1 = (y0 - r2 * x0) / (r1 - r2)
    return qp + c1 * np.exp(r1 * t) + (x0 - c1) * np.exp(r2 * t)


@pytest.mark.parametrize("hold", ["constant", "linear"])
def test_under_critical_and_over_damped_modes_match_closed_forms(hold):
    # c = alpha + beta lambda with alpha = 3.6, beta = 0.1: lambda = 1 over-damped (zeta 1.85),
    # lambda = 4 critically damped (c = 4 = 2 sqrt(4)), lambda = 100 under-damped (zeta 0.68)
    lam = np.array([1.0, 4.0, 100.0])
    alpha, beta = 3.6, 0.1
    c = alpha + beta * lam
    assert c[1] ** 2 == 4 * lam[1]
    q0, v0 = np.array([0.3, -0.2, 0.1]), np.array([1.0, 2.0, -3.0])
    p0, rate = np.array([2.0, -1.0, 5.0]), (np.array([0.5, 3.0, -2.0]) if hold == "linear" else np.zeros(3))
    for dt in (1e-5, 0.01, 0.7):
        n = min(int(round(3.5 / dt)), 3000)
        t = np.arange(n + 1) * dt
        loads = p0 + rate * t[:, None]
        q, _ = integrate_modes(lam, alpha, beta, dt, loads, q0, v0, hold=hold)
        for i in range(3):
            expected = closed_form(lam[i], c[i], q0[i], v0[i], p0[i], rate[i], t)
            assert np.abs(q[:, i] - expected).max() < 1e-12 * (1 + np.abs(expected).max()), (dt, i)


def test_near_critical_damping_is_continuous():
    lam = np.full(1, 9.0)
    results = []
    for zeta in (1 - 1e-9, 1.0, 1 + 1e-9):
        q, qd = integrate_modes(lam, 6.0 * zeta, 0.0, 0.05, np.full((41, 1), 2.0), np.ones(1), np.ones(1))
        results.append(q[:, 0])
    assert np.abs(results[0] - results[1]).max() < 1e-8
    assert np.abs(results[2] - results[1]).max() < 1e-8


def test_batched_states_and_rayleigh_targets():
    lam = np.array([4.0, 50.0, 900.0])
    step = modal_step(lam, 0.2, 0.001, 0.02)
    q = np.random.default_rng(0).standard_normal((3, 5))
    qd = np.zeros((3, 5))
    p = np.ones(3)
    qb, _ = advance(step, q, qd, p[:, None], p[:, None])
    for j in range(5):
        qs, _ = advance(step, q[:, j], qd[:, j], p, p)
        assert np.allclose(qb[:, j], qs, rtol=1e-15)
    alpha, beta = rayleigh_coefficients(0.02, 1.0, 0.05, 20.0)
    z = damping_ratios((2 * np.pi * np.array([1.0, 20.0])) ** 2, alpha, beta)
    assert z == pytest.approx([0.02, 0.05], rel=1e-12)
    with pytest.raises(HitogataError, match="alpha"):
        rayleigh_coefficients(0.5, 1.0, 0.01, 20.0)  # would need negative beta
    # a rigid-body mode (lambda = 0, alpha = 0) under a constant load accelerates uniformly
    q, qd = integrate_modes(np.zeros(1), 0.0, 0.0, 0.1, np.full((21, 1), 3.0))
    assert q[-1, 0] == pytest.approx(3.0 * 2.0**2 / 2, rel=1e-13) and qd[-1, 0] == pytest.approx(6.0, rel=1e-13)
    with pytest.raises(HitogataError, match="eigenvalues"):
        modal_step(np.array([np.nan, 4.0]), 0.1, 0.0, 0.01)
    with pytest.raises(HitogataError, match="dt"):
        modal_step(lam, 0.1, 0.0, 0.0)
