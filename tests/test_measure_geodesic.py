"""Surface lengths: exact geodesics against the helix on a cylinder."""

import numpy as np
import pytest
from trimesh import remesh

from measure_shapes import circle, prism

from hitogata.errors import HitogataError
from hitogata.measure.geodesic import SurfaceGeodesics

R, H, N = 0.1, 0.3, 720


@pytest.fixture(scope="module")
def cylinder():
    return prism(circle(R, N), H, rings=4)


@pytest.mark.parametrize("steps", [0, 90, 200, 350])
def test_geodesic_on_a_cylinder_is_the_helix(cylinder, steps):
    v, f = cylinder
    top = 3 * N + steps  # vertex `steps` places round the top ring from the start of the bottom ring
    length = SurfaceGeodesics(v, f).length(0, top)
    # The prism's side unrolls into a flat strip of facets of width 2R sin(π/N): the exact
    # geodesic is a straight line there; the helix is its limit as N grows.
    unrolled = np.hypot(H, steps * 2 * R * np.sin(np.pi / N))
    helix = np.hypot(H, R * 2 * np.pi * steps / N)
    assert length == pytest.approx(unrolled, rel=1e-9)
    assert length == pytest.approx(helix, rel=1e-5)


def test_geodesic_length_does_not_depend_on_the_tessellation(cylinder):
    v, f = cylinder
    finer_v, finer_f = remesh.subdivide(v, f)  # midpoint subdivision: same surface, 4× the triangles
    a, b = 0, 3 * N + 200
    finer = SurfaceGeodesics(finer_v, finer_f).length(a, b)
    assert finer == pytest.approx(SurfaceGeodesics(v, f).length(a, b), rel=1e-9)


def test_path_through_waypoints_adds_the_legs(cylinder):
    v, f = cylinder
    paths = SurfaceGeodesics(v, f)
    via = N + 100
    assert paths.length(0, via, 3 * N) == pytest.approx(paths.length(0, via) + paths.length(via, 3 * N), rel=1e-12)
    assert paths.length(5, 5) == 0.0


def test_unknown_vertex_is_a_one_line_error(cylinder):
    v, f = cylinder
    with pytest.raises(HitogataError, match="geodesic vertex"):
        SurfaceGeodesics(v, f).length(0, len(v) + 3)
