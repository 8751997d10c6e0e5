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


def skewed_tube(radius: float, around: int, rings: int) -> tuple[np.ndarray, np.ndarray]:
    """An open tube whose quads are all split by the diagonal that rises against the +angle
    direction: the edge graph is short for paths winding one way and a staircase the other."""
    t = 2 * np.pi * np.arange(around) / around
    step = 2 * np.pi * radius / around  # ring spacing = the step round: square quads
    v = np.array([[radius * np.cos(a), r * step, radius * np.sin(a)] for r in range(rings) for a in t])
    f = []
    for r in range(rings - 1):
        for k in range(around):
            a, b = r * around + k, r * around + (k + 1) % around
            c, d = a + around, b + around
            f += [[a, b, c], [b, d, c]]  # diagonal b–c: from (r, k+1) up to (r+1, k)
    return v, np.array(f, dtype=np.int64)


def test_the_shortest_route_not_the_first_locally_shortest_one():
    # 150° round one way, 210° the other, 42 rings up. The edge graph's shortest path winds the
    # long way (its diagonals run straight there); straightened, it stays a locally shortest
    # helix on that side, 15 % longer than the true shortest, the helix the short way round.
    around, rings, radius = 72, 43, 0.1
    v, f = skewed_tube(radius, around, rings)
    step = 2 * np.pi * radius / around
    end = (rings - 1) * around + 30  # 30 steps = 150° in the +angle direction
    short_way = np.hypot(30 * 2 * radius * np.sin(np.pi / around), (rings - 1) * step)
    long_way = np.hypot(42 * 2 * radius * np.sin(np.pi / around), (rings - 1) * step)
    assert long_way > 1.1 * short_way
    assert SurfaceGeodesics(v, f).length(0, end) == pytest.approx(short_way, rel=1e-6)


@pytest.mark.parametrize("sex", ["female", "male"])
def test_arm_length_does_not_depend_on_the_skinning(sex, request):
    # Elbow straight: on the DQS arm the shoulder-to-elbow leg once followed a locally shortest
    # route round the arm, 32.8 cm against 26.2 cm straight on the female default (LBS 27.0 cm).
    from hitogata.measure import measure
    from hitogata.posing import pose_body

    body = request.getfixturevalue(sex)
    arm = {}
    for skinning in ("lbs", "dqs"):
        arm[skinning] = measure(pose_body(body, clinical={"forearm_r.flexion": 0.0}, skinning=skinning)).arm_length
    assert arm["dqs"] == pytest.approx(arm["lbs"], abs=0.003)
