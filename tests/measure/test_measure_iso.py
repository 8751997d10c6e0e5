"""The ISO 8559-1 measurements added for made-to-measure: both waists, the neck at its level,
armscye, across widths, shoulder length, waist-to-hip and crotch lengths."""

import numpy as np
import pytest

from measure_shapes import circle, prism

from hitogata.body import Body
from hitogata.measure import measure
from hitogata.measure.measurements import MEASUREMENT_NAMES
from hitogata.measure.sections import arc_tape, tape_girth
from hitogata.geometry.topology import topology
from hitogata.measure.landmarks import body_landmarks


@pytest.mark.parametrize("sex", ["female", "male"])
@pytest.mark.parametrize("stature, bmi", [(1.50, 18.0), (1.50, 33.0), (1.95, 18.0), (1.95, 33.0)])
def test_every_measurement_holds_at_the_extremes(sex, stature, bmi):
    # The corners of the supported range (BMI 33: about the heaviest the shape solver allows at 150 cm).
    m = measure(Body.from_measurements(sex=sex, age=30, stature=stature, mass=bmi * stature**2))
    values = np.array([m.get(n) for n in MEASUREMENT_NAMES])
    assert np.isfinite(values).all() and (values > 0).all()
    assert m.waist_girth <= m.omphalion_waist_girth + 0.005 and m.waist_girth < m.underbust_girth
    assert m.neck_girth < m.armscye_girth < m.chest_girth and m.armscye_girth > m.upper_arm_girth
    assert m.across_back_width < m.shoulder_width and m.across_front_width < m.chest_girth / 2
    assert 0.4 < m.shoulder_length / (m.shoulder_width / 2) < 0.8  # neck point to acromion, of half the width
    assert 0.08 < m.waist_to_hip_length / m.stature < 0.18
    assert 0.3 < m.crotch_length / m.stature < 0.6


def neck_girth_at(body, fraction: float) -> float:
    """The girth ⊥ the neck's axis (base neck joint → head joint) at a fraction of it."""
    base, head = (body.rig.heads[body.rig.index(name)] for name in ("neck01", "head"))
    point = base + fraction * (head - base)
    return tape_girth(body.vertices, topology(body.faces), point, head - base, point).girth


def waist_girth_at(body, y: float) -> float:
    """The horizontal trunk girth at height y, round the spine."""
    centre = np.array([0.0, y, body.rig.heads[body.rig.index("spine03"), 2]])
    return tape_girth(body.vertices, topology(body.faces), centre, np.array([0.0, 1.0, 0.0]), centre).girth


@pytest.mark.parametrize("sex", ["female", "male"])
def test_neck_and_waist_are_where_the_part_is_narrowest(sex, request):
    # The neck girth's and the waist's levels are found on the surface: moving the plane along the
    # part either way gives a larger girth (no rig joint decides).
    body = request.getfixturevalue(sex)
    marks, v = body_landmarks(body), body.vertices
    level = marks.neck_level
    assert neck_girth_at(body, level) < min(neck_girth_at(body, level - 0.1), neck_girth_at(body, level + 0.1))
    y = marks.waist_front.at(v)[1]
    assert waist_girth_at(body, y) < min(waist_girth_at(body, y - 0.03), waist_girth_at(body, y + 0.03))
    assert v[marks.omphalion, 1] < y < v[marks.underbust, 1]
    assert measure(body).waist_girth == pytest.approx(waist_girth_at(body, y), abs=1e-9)


def test_arc_tape_lies_on_the_surface_and_bridges_hollows():
    r, n = 0.1, 720
    v, f = prism(circle(r, n), 1.0, rings=3)
    topo = topology(f)
    ends = (np.array([-r, 0.5, 0.0]), np.array([0.0, 0.5, -r]), np.array([r, 0.5, 0.0]))
    half = arc_tape(v, topo, ends, np.array([0.0, 0.5, 0.0]))
    assert half.girth == pytest.approx(np.pi * r, rel=1e-5)  # half the circle, over the back
    assert np.allclose(half.path[0], ends[0]) and np.allclose(half.path[-1], ends[2])
    # A notch in the back (a hollow between the shoulder blades): the tape bridges it.
    outline = circle(r, n)
    notch = np.abs(np.arctan2(-outline[:, 1], outline[:, 0]) - np.pi / 2) < 0.2  # round the back (-z)
    outline[notch] *= 0.8
    v, f = prism(outline, 1.0, rings=3)
    bridged = arc_tape(v, topology(f), ends, np.array([0.0, 0.5, 0.0]))
    assert bridged.girth == pytest.approx(half.girth, rel=2e-3)


def test_a_cut_tape_does_not_depend_on_the_mesh():
    # The armscye's tape is cut below a line (under the arm): the cut's ends are where the
    # section crosses it, not the nearest section points, so a finer mesh gives the same tape.
    outline = circle(0.1, 64)
    coarse, fine = prism(outline, 1.0, rings=3), prism(outline, 1.0, rings=41)
    origin, normal = np.array([0.0, 0.5, 0.0]), np.array([1.0, 0.0, 0.0])
    above = (np.array([0.0, 0.5, 0.0]), np.array([0.0, 1.0, 0.0]), -0.013)
    girths = [tape_girth(v, topology(f), origin, normal, origin, above=above).girth for v, f in (coarse, fine)]
    assert girths[0] == pytest.approx(girths[1], abs=1e-12)
    # the plane cuts the prism in a 0.2 m by 1 m rectangle: its part above the cut, closed by the cut
    assert girths[0] == pytest.approx(2 * (0.5 + 0.013) + 2 * 0.2, abs=1e-12)
