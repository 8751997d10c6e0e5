"""The fine skin: fine enough that a 10 cm line crosses ≥ 20 triangles at elbow and knee, and it
measures the same stretch as the skin where the deformation is smooth."""

import numpy as np
import pytest

from hitogata.body import Body
from hitogata.measure.body_lines import body_lines
from hitogata.skin.fine_skin import LEVELS
from hitogata.measure.strain import skin_strain
from hitogata.measure.zones import zone_strains
from hitogata.posing import poser_for
from hitogata.skin.fine_skin import body_fine_skin
from hitogata.skin.fine_skin import body_fine_skinning

LINES_10CM = ("elbow_posterior", "elbow_anterior", "knee_anterior", "knee_posterior")


@pytest.fixture(scope="module", params=["female", "male", "short thin", "tall heavy"])
def body(request, female, male):
    if request.param == "short thin":
        return Body.from_measurements(sex="female", age=30, stature=1.50, mass=18.0 * 1.50**2)
    if request.param == "tall heavy":
        return Body.from_measurements(sex="male", age=30, stature=1.95, mass=35.0 * 1.95**2)
    return {"female": female, "male": male}[request.param]


def test_a_10cm_line_crosses_at_least_20_triangles_at_elbow_and_knee(body):
    fine = body_fine_skin(body)
    assert len(fine.faces) == 16 * len(body.faces) and LEVELS == 2
    coarse_lines, fine_lines = body_lines(body), body_lines(body, fine.vertices, fine.faces)
    for name in LINES_10CM:
        line = fine_lines[name]
        assert line.crossings >= 20, (name, line.crossings)
        assert line.crossings >= 3.5 * coarse_lines[name].crossings
        assert 0.09 <= line.length(fine.vertices) <= 0.115  # ±5 cm along the limb, over the skin
    # Loop's rest surface is the skin smoothed: a closed line round the limb within 2 % of the skin's
    for name in ("elbow_circumference", "knee_circumference"):
        assert fine_lines[name].length(fine.vertices) == pytest.approx(
            coarse_lines[name].length(body.vertices), rel=0.02
        )


def test_fine_and_coarse_stretch_agree_on_a_smooth_deformation(female):
    """A smooth nonlinear map of the whole body: each zone's mean stretch and area change agree to
    0.15 percentage points (of 3–16 %), and 99 % of the coarse triangles' stretch with their 16 fine
    ones' mean to 5 % (Loop's rest surface is the skin smoothed, its tangent planes not the facets')."""
    fine = body_fine_skin(female)

    def bend(x):
        y = x[:, 1]
        return np.stack([x[:, 0] * (1 + 0.2 * np.sin(3 * y)), 1.05 * y, x[:, 2] + 0.3 * x[:, 0] ** 2], axis=1)

    coarse = skin_strain(female.vertices, bend(female.vertices), female.faces)
    finer = skin_strain(fine.vertices, bend(fine.vertices), fine.faces)
    zc, zf = zone_strains(female, coarse), zone_strains(female, finer)
    for name in zc:
        assert zf[name].stretch_mean == pytest.approx(zc[name].stretch_mean, abs=0.15)
        assert zf[name].area_change == pytest.approx(zc[name].area_change, abs=0.15)
    area = finer.rest_area
    n = len(female.faces)
    mean = np.bincount(fine.parent, area * finer.stretch_max, n) / np.bincount(fine.parent, area, n)
    ok = np.isfinite(coarse.stretch_max) & np.isfinite(mean)
    assert np.percentile(np.abs(mean - coarse.stretch_max)[ok], 99) < 0.05


def test_the_fine_skin_is_posed_by_the_same_skinning(female):
    """At rest it is its rest surface; a rigid motion of the whole body moves it rigidly; an elastic
    difference of the coarse skin is carried by the same stencils (a uniform one unchanged)."""
    poser = poser_for(female)
    fs = body_fine_skinning(female)
    rest = poser.pose()
    assert np.abs(fs.surface(rest.pose, "lbs") - fs.fine.vertices).max() < 1e-12
    turn = np.eye(4)
    turn[:3, :3] = [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]
    turned = poser.pose(root=turn)
    assert np.abs(fs.surface(turned.pose, "dqs") - fs.fine.vertices @ turn[:3, :3].T).max() < 1e-9
    assert np.abs(fs.fine.carry(female.vertices) - fs.fine.vertices).max() < 1e-12
    for method in ("lbs", "dqs"):
        posed = poser.pose(clinical={"shank_l.flexion": np.radians(90)}, skinning=method)
        fine_posed = fs.surface(posed.pose, method)
        push = posed.vertices + np.array([0.0, 0.0, 0.01])
        assert np.abs(fs.surface(posed.pose, method, push) - fine_posed - [0.0, 0.0, 0.01]).max() < 1e-12
