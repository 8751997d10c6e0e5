"""A garment as a membrane in contact (IPC) with bodies whose answers are known: rigid cylinders and
ellipses (Laplace's law, force balance) and a soft thick-walled cylinder (Lamé); the garment files."""

from __future__ import annotations

import re

import numpy as np
import pytest

from hitogata.errors import HitogataError
from hitogata.garment.contact.equilibrium import settle
from hitogata.garment.contact.membrane import Membrane, fabric_terms
from hitogata.garment.contact.pressure import node_pressure
from hitogata.garment.contact.spec import load_garment, shipped_garments
from hitogata.garment.contact.tube import build_tube
from hitogata.garment.contact.verify import (
    elliptic_cylinder,
    elliptic_rings,
    lame_indentation,
    soft_annulus,
    straight_stations,
)
from hitogata.garment.fabric import Fabric
from hitogata.geometry.normals import vertex_areas
from samples import soft_cylinder

KNIT = Fabric((0.0, 0.1, 0.3, 0.6), (0.0, 30.0, 120.0, 400.0))  # N/m: a knit stiffening with strain


def dress_tube(a: float, b: float, length: float, garment: tuple[int, int], skin: tuple[int, int], ease: float,
               fabric: Fabric = KNIT):
    """A tube `ease` smaller round than an elliptic cylinder (semi-axes a, b), settled on it from 2 mm outside."""
    stations = straight_stations(length, garment[1])
    perimeter = np.pi * (3 * (a + b) - np.sqrt((3 * a + b) * (a + 3 * b)))  # Ramanujan
    tube = build_tube(stations, garment[0], np.full(garment[1], (1 + ease) * perimeter), fabric, Fabric.linear(100.0),
                      30.0)
    body = elliptic_cylinder(a, b, length, *skin)
    start = elliptic_rings(stations, a + 0.002, b + 0.002, garment[0])
    return tube, body, settle(tube, start, body)


def test_fabric_terms_are_the_curve_and_its_integral():
    strain = np.linspace(-0.1, 0.9, 41)
    phi, tension, stiffness = fabric_terms(KNIT, strain)
    assert np.allclose(tension, KNIT.tension(strain))
    h = 1e-7
    assert np.allclose((fabric_terms(KNIT, strain + h)[0] - phi) / h, tension, atol=1e-3)
    assert phi[strain <= 0].max() == 0.0 and stiffness[strain > 0.6].min() == pytest.approx(280.0 / 0.3)


def test_membrane_gradient_is_the_energy_derivative():
    rng = np.random.default_rng(3)
    rest = rng.normal(size=(6, 3))
    faces = np.array([[0, 1, 2], [1, 3, 2], [2, 3, 4], [3, 5, 4]])
    membrane = Membrane.build(rest, faces, rng.normal(size=(4, 3)), KNIT, Fabric.linear(50.0), 20.0)
    x = 1.2 * rest + 0.05 * rng.normal(size=rest.shape)
    energy, gradient, hessian = membrane.derivatives(x)
    h = 1e-6
    numeric = np.array([[(membrane.energy(x + h * np.eye(18)[3 * i + j].reshape(6, 3)) - energy) / h
                         for j in range(3)] for i in range(6)])
    assert np.allclose(numeric, gradient, atol=1e-3 * np.abs(gradient).max())
    assert np.linalg.eigvalsh(hessian.toarray()).min() > -1e-9 * np.abs(hessian).max()


def test_rigid_cylinder_pressure_is_tension_over_radius_and_balances_it():
    r, length = 0.05, 0.03
    tube, body, eq = dress_tube(r, r, length, (96, 13), (48, 4), -0.2)
    assert eq.converged and 0 < eq.min_distance < 1e-3
    tension = tube.membrane.tensions(eq.garment)[0]
    assert tension.std() < 0.02 * tension.mean()  # uniform round the section: no friction
    z = body.points[:, 2]
    band = (z > 0.005) & (z < length - 0.005)
    force = -np.einsum("ni,ni->n", eq.body_force, body.points * [1, 1, 0]) / r  # pressing in
    areas = vertex_areas(body.points, body.faces)
    pressure = force[band].sum() / areas[band].sum()
    assert pressure == pytest.approx(tension.mean() / r, rel=0.01)  # Laplace: P = T / r
    assert node_pressure(body.points, body.faces, eq.body_force)[band].mean() == pytest.approx(pressure, rel=0.01)
    # the half section's contact force balances the tension at its two cut edges: 2 T L
    upper = body.points[:, 1] > 1e-9
    assert -eq.body_force[upper, 1].sum() == pytest.approx(2 * tension.mean() * length, rel=0.01)
    total = np.abs(eq.body_force[:, :2]).sum()
    assert np.abs(eq.body_force[:, :2].sum(axis=0)).max() < 1e-4 * total  # round the section, the pushes cancel


def test_ellipse_pressure_follows_the_local_curvature():
    a, b = 0.06, 0.04
    tube, body, eq = dress_tube(a, b, 0.004, (160, 5), (160, 2), -0.2, Fabric.linear(500.0))
    assert eq.converged
    tension = float(tube.membrane.tensions(eq.garment)[0].mean())
    pressure = node_pressure(body.points, body.faces, eq.body_force)
    areas = vertex_areas(body.points, body.faces)
    angle = np.arctan2(body.points[:, 1] / b, body.points[:, 0] / a)

    def sensor(at: float) -> float:  # five skin nodes round the section (a pressure sensor's patch, ±4 mm)
        chosen = np.abs(np.angle(np.exp(1j * (angle - at)))) < 2.5 * 2 * np.pi / 160
        return float((pressure * areas)[chosen].sum() / areas[chosen].sum())

    flat, round_ = sensor(np.pi / 2), sensor(0.0)
    curvature_flat, curvature_round = b / a ** 2, a / b ** 2
    assert flat / round_ == pytest.approx(curvature_flat / curvature_round, rel=0.03)
    assert round_ == pytest.approx(tension * curvature_round, rel=0.05)  # the window's mean curvature is 1 % less
    # the half section's force balances the tension: 2 T L
    upper = body.points[:, 1] > 1e-9
    assert -eq.body_force[upper, 1].sum() == pytest.approx(2 * tension * 0.004, rel=0.01)


@pytest.mark.parametrize("nu", [0.3, 0.45, 0.49])  # 0.49: the tissue's (materials.toml)
def test_soft_cylinder_indentation_is_lames(nu):
    inner, outer, length, E = 0.03, 0.05, 0.004, 20e3
    body = soft_annulus(inner, outer, length, E, nu, 6, 96, 1)
    stations = straight_stations(length, 5)
    tube = build_tube(stations, 96, np.full(5, 0.85 * 2 * np.pi * outer), Fabric.linear(300.0), Fabric.linear(300.0),
                      30.0)
    eq = settle(tube, elliptic_rings(stations, outer + 0.002, outer + 0.002, 96), body)
    assert eq.converged
    surface = np.unique(body.faces)
    rest = body.points
    radial = rest[surface, :2] / np.linalg.norm(rest[surface, :2], axis=1)[:, None]
    indentation = -np.einsum("ni,ni->n", (eq.body - rest)[surface, :2], radial)
    assert indentation.std() < 0.01 * indentation.mean()
    pressure = node_pressure(rest, body.faces, eq.body_force)[surface].mean()  # on the rest area, as Lamé's
    assert indentation.mean() == pytest.approx(lame_indentation(pressure, inner, outer, E, nu), rel=0.03)
    assert 0.02e-3 < indentation.mean() < 1e-3
    # the pressure on the indented skin's area is the tension over the indented radius
    tension = float(tube.membrane.tensions(eq.garment)[0].mean())
    now = node_pressure(eq.body, body.faces, eq.body_force)[surface].mean()
    assert now == pytest.approx(tension / (outer - indentation.mean()), rel=0.01)


def test_newton_steps_by_reused_factors_reach_the_exact_steps_equilibrium(monkeypatch):
    """Steps by conjugate gradients preconditioned with an earlier step's factors: fewer factorizations, the
    same equilibrium as every step factored (the soft cylinder: the tissue's stiffness with the barrier's)."""
    from hitogata.fem import factor
    from hitogata.garment.contact import equilibrium

    body, stations, tube, start = soft_cylinder()
    factored = []
    counted = factor.factorize
    monkeypatch.setattr(factor, "factorize", lambda *args, **kw: factored.append(1) or counted(*args, **kw))
    reused = settle(tube, start, body)
    reused_factors = len(factored)
    monkeypatch.setattr(equilibrium, "REUSE_ITERATIONS", 0)
    exact = settle(tube, start, body)
    assert reused.converged and exact.converged
    assert reused_factors < reused.iterations and len(factored) - reused_factors == exact.iterations
    surface = np.unique(body.faces)
    indentation = np.linalg.norm((exact.body - body.points)[surface], axis=1).mean()
    # the same equilibrium to Newton's tolerance: the tissue's nodes within 1 % of its indentation
    assert np.abs(reused.body - exact.body).max() < 0.01 * indentation
    assert np.abs(reused.garment - exact.garment).max() < equilibrium.TOLERANCE


def test_shipped_garments_load():
    shipped = shipped_garments()
    assert {"legging", "stocking", "sleeve", "top"} <= set(shipped)
    legging = load_garment("legging")
    assert legging.segment == "leg" and legging.ease == pytest.approx(-0.2)
    assert legging.levels == ("ankle", "calf", "knee", "thigh")
    stocking = load_garment("stocking")
    assert stocking.relaxed == pytest.approx({"ankle": 0.141, "calf": 0.252, "knee": 0.269, "thigh": 0.431})
    assert stocking.course.tension(0.4) == pytest.approx(130.0)
    assert load_garment("sleeve").segment == "arm" and load_garment("top").segment == "trunk"


@pytest.mark.parametrize("text, message", [
    ('segment = "leg"\n[relaxed]\nankle = "0cm"\n[fabric]\ncourse = "400N/m"\n',
     "relaxed.ankle: '0cm'; allowed a circumference > 0"),
    ('segment = "leg"\n[relaxed]\nankle = "-3cm"\n[fabric]\ncourse = "400N/m"\n', "relaxed.ankle: '-3cm' is out of range"),
    ('segment = "leg"\n[relaxed]\nwrist = "14cm"\n[fabric]\ncourse = "400N/m"\n', "relaxed: unknown key 'wrist'"),
    ('segment = "neck"\nease = "-10%"\n[fabric]\ncourse = "400N/m"\n', "file.segment: 'neck'; allowed leg, arm, trunk"),
    ('ease = "-10%"\n[fabric]\ncourse = "-4N/m"\n', "fabric.course: '-4N/m' is out of range"),
    ('ease = "-10%"\n[fabric]\n', "fabric: missing key 'course'"),
    ('ease = "-10%"\nlevels = ["ankle", "hip"]\n[fabric]\ncourse = "400N/m"\n',
     "file.levels: 'hip'; allowed levels of the leg: ankle, calf, knee, thigh"),
    ('ease = "-10%"\n[relaxed]\nankle = "14cm"\n[fabric]\ncourse = "400N/m"\n', "give one of `ease`, a [relaxed] table"),
    ('ease = "-10%"\n[fabric]\ncourse = "missing.csv"\n', "missing.csv: no such fabric file"),
])
def test_garment_file_mistakes_are_one_line(tmp_path, text, message):
    path = tmp_path / "g.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(HitogataError) as err:
        load_garment(path)
    assert message in str(err.value) and str(tmp_path) in str(err.value) and "\n" not in str(err.value)


def test_unknown_garment_name_lists_the_shipped():
    with pytest.raises(HitogataError, match="allowed a garment file or a shipped garment: legging, legging_mesh, sleeve"):
        load_garment("no-such-garment")


def test_a_garment_smaller_than_its_fabric_can_stretch_is_refused(female, tmp_path):
    from hitogata.garment.contact.dressing import prepare

    csv = tmp_path / "knit.csv"
    csv.write_text("strain_%,tension_N/m\n0,0\n50,100\n", encoding="utf-8")
    path = tmp_path / "tight.toml"
    path.write_text('segment = "leg"\n[relaxed]\nankle = "10cm"\ncalf = "25cm"\n[fabric]\ncourse = "knit.csv"\n',
                    encoding="utf-8")
    with pytest.raises(HitogataError) as err:
        prepare(female, load_garment(path))
    message = str(err.value)
    assert f"{path}: relaxed.ankle: 10.0 cm is smaller than the fabric can stretch to" in message
    assert re.search(r"near the ankle \((19|20)\.\d cm round: 9\d % strain\); allowed at least 1[23]\.\d cm there "
                     r"\(the fabric's test reaches 50 %\)$", message) and "\n" not in message



@pytest.mark.slow
def test_leg_tissue_lies_between_bone_and_skin(female):
    """The legging's tissue mesh on the default female: every tet positive, the bone held, the skin layer
    as thick as the volume model's (or half the tissue where it is thinner), the outer nodes on the
    sections' hulls, its surface closed round the limb and at the ends."""
    from hitogata.garment.contact.dressing import prepare
    from hitogata.garment.contact.tissue import LEAST_TISSUE, limb_tissue
    from hitogata.geometry.mesh_checks import enclosed_volume
    from hitogata.geometry.tets import signed_volumes
    from hitogata.volume.anatomy import skin_thickness

    _, tube, _, _, _, radii = prepare(female, load_garment("legging"))
    tissue = limb_tissue(female, "leg", tube.stations, radii)
    body, stations, chosen = tissue.body, tube.stations, tissue.stations
    assert body.stiffness is not None and body.fixed is not None
    assert (signed_volumes(body.points, tissue.tets) > 0).all()
    outer = body.points[tissue.outer]
    # the outer nodes on each chosen station's plane and hull, at every second angle
    along = np.einsum("mni,mi->mn", outer - stations.origins[chosen][:, None], stations.axis[chosen])
    assert np.abs(along).max() < 1e-9
    distance = np.linalg.norm(outer - stations.origins[chosen][:, None], axis=2)
    assert distance == pytest.approx(radii[chosen][:, ::2], abs=1e-9)
    held = body.fixed.reshape(-1, 3).all(axis=1)
    assert held.sum() == tissue.outer.size  # the bone: one node under each outer node
    m, n = tissue.outer.shape
    bone = body.points[held].reshape(n, m, 3).transpose(1, 0, 2)  # nodes (i, j, k): k fastest
    depth = np.linalg.norm(outer - bone, axis=2)
    assert depth.min() >= LEAST_TISSUE - 1e-9
    skin_in = body.points[tissue.outer - 2 * n * m]  # two layers in: the skin region's inner face
    skin = skin_thickness(female.bmi, female.params.sex)
    assert np.linalg.norm(outer - skin_in, axis=2) == pytest.approx(np.minimum(skin, 0.5 * depth), rel=1e-6)
    asymmetry = abs(body.stiffness - body.stiffness.T).max()
    assert asymmetry < 1e-9 * abs(body.stiffness).max()
    assert enclosed_volume(*tissue.closed_surface(body.points)) > 0
