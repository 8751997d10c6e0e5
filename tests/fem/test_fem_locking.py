"""Volumetric locking: a cantilever's bending frequency as Poisson's ratio approaches 0.5, P1 vs P2,
and P2 on the mean dilatation (the elastic body's default)."""

import numpy as np

from hitogata.fem.verify.box_mesh import box_mesh
from hitogata.fem.verify.locking import poisson_sweep


def test_linear_tets_lock_quadratic_tets_a_little_mean_dilatation_not():
    points, tets = box_mesh((1.0, 0.1, 0.1), (20, 2, 2))  # 480 tets; P2 has 3,075 dofs
    clamped = np.flatnonzero(points[:, 0] < 1e-12)
    sweep = poisson_sweep(points, tets, clamped, E=1e6, rho=1000.0, nus=[0.3, 0.4, 0.45, 0.49, 0.499])
    print("\nfirst bending frequency of the 1 x 0.1 x 0.1 m cantilever vs nu:\n" + sweep.table())
    p1_rise = sweep.p1 / sweep.p1[0] - 1
    p2_rise = sweep.p2 / sweep.p2[0] - 1
    mean_rise = sweep.p2_mean / sweep.p2_mean[0] - 1
    # beam theory: the bending frequency hardly depends on nu; a rise is the element's artefact
    assert np.all(np.diff(sweep.p1) > 0)
    assert p1_rise[3] > 0.5 and p1_rise[4] > 2.0  # P1: +99 % at 0.49, +320 % at 0.499
    assert p2_rise[3] < 0.03 and p2_rise[4] < 0.04  # P2: +2.1 %, +2.7 %
    assert 0.015 < p2_rise[3]  # ... still some locking at the tissue's 0.49
    assert np.all(mean_rise < 0.4 * p2_rise[1:].max()) and mean_rise[3] < 0.01  # +0.7 % at 0.49, +0.8 % at 0.499
    assert abs(sweep.p2[0] / 0.50687 - 1) < 0.01
