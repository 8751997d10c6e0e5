"""Tape girths of planar sections against analytic values on synthetic prisms."""

import numpy as np
import pytest
from scipy.special import ellipe

from measure_shapes import circle, ellipse, prism, ramanujan_ii, two_circles

from hitogata.measure.sections import section, tape_girth
from hitogata.geometry.topology import topology

UP = np.array([0.0, 1.0, 0.0])


def girth(vertices, faces, origin, normal, centre=None):
    centre = origin if centre is None else centre
    origin, normal, centre = (np.asarray(x, dtype=float) for x in (origin, normal, centre))
    return tape_girth(vertices, topology(faces), origin, normal, centre).girth


def test_cylinder_girth_is_the_circle_perimeter():
    r, n = 0.1, 2048
    v, f = prism(circle(r, n), 0.3, rings=3)
    # The section of a prism is its inscribed polygon: 2 n r sin(π/n) exactly, → 2πr.
    assert girth(v, f, [0, 0.11, 0], UP) == pytest.approx(2 * n * r * np.sin(np.pi / n), rel=1e-12)
    assert girth(v, f, [0, 0.11, 0], UP) == pytest.approx(2 * np.pi * r, rel=1e-6)


def test_oblique_cut_of_a_cylinder_is_an_ellipse():
    r, tilt = 0.1, np.radians(35)
    v, f = prism(circle(r, 2048), 0.5, rings=2)
    normal = [np.sin(tilt), np.cos(tilt), 0.0]
    expected = ramanujan_ii(r / np.cos(tilt), r)
    assert girth(v, f, [0, 0.25, 0], normal) == pytest.approx(expected, rel=1e-6)


def test_elliptic_section_converges_to_the_exact_perimeter():
    a, b = 0.15, 0.09
    exact = 4 * a * ellipe(1 - (b / a) ** 2)  # complete elliptic integral of the second kind
    assert ramanujan_ii(a, b) == pytest.approx(exact, rel=1e-9)
    errors = []
    for n in (64, 128, 256, 512, 1024):
        v, f = prism(ellipse(a, b, n), 0.3, rings=2)
        errors.append(abs(girth(v, f, [0, 0.1, 0], UP) - exact))
    assert errors[-1] < 2e-6 * exact
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all(ratios > 3.5)  # second-order convergence: halving the spacing quarters the error


def test_tape_bridges_hollows_convex_hull():
    # Two overlapping circles: the tape spans the two notches, hull perimeter 2πr + 4d.
    r, d = 0.1, 0.06
    v, f = prism(two_circles(r, d, 4000), 0.3, rings=2)
    assert girth(v, f, [0, 0.15, 0], UP) == pytest.approx(2 * np.pi * r + 4 * d, rel=1e-5)
    sec = section(v, topology(f), np.array([0, 0.15, 0]), UP)
    outline = np.linalg.norm(np.diff(np.vstack([sec.points, sec.points[:1]]), axis=0), axis=1)
    assert sec.n_loops == 1 and outline.max() < 0.01  # one loop, densely sampled


def test_only_the_loops_round_the_centre_count():
    # Two separate cylinders in one mesh; the centre picks one of them.
    v1, f1 = prism(circle(0.1, 512), 0.3)
    v2, f2 = prism(circle(0.05, 512), 0.3)
    v2 = v2 + [0.5, 0.0, 0.0]
    v, f = np.vstack([v1, v2]), np.vstack([f1, f2 + len(v1)])
    assert girth(v, f, [0, 0.1, 0], UP, centre=[0.0, 0.0, 0.0]) == pytest.approx(2 * np.pi * 0.1, rel=1e-4)
    assert girth(v, f, [0, 0.1, 0], UP, centre=[0.5, 0.2, 0.0]) == pytest.approx(2 * np.pi * 0.05, rel=1e-4)
    assert np.isnan(girth(v, f, [0, 0.1, 0], UP, centre=[0.3, 0.1, 0.0]))  # between them: no loop


def test_centre_off_the_plane_is_projected_onto_it():
    v, f = prism(circle(0.1, 512), 0.3)
    assert girth(v, f, [0, 0.1, 0], UP, centre=[0.0, 0.25, 0.0]) == pytest.approx(2 * np.pi * 0.1, rel=1e-4)


def test_tape_keeps_to_the_part_when_loops_join():
    # One loop round two joined lobes (circles r at x = ±d): with the left lobe's skin
    # only, the tape goes round that lobe and the crossing between them.
    r, d = 0.1, 0.06
    v, f = prism(two_circles(r, d, 4000), 0.3, rings=2)
    left = v[:, 0] <= 0.0
    topo = topology(f)
    origin = np.array([0.0, 0.15, 0.0])
    both = tape_girth(v, topo, origin, UP, origin).girth
    one = tape_girth(v, topo, origin, UP, origin, part=left).girth
    # Left lobe: the arc of the circle outside x > 0 closed by the chord at x = 0.
    half_chord = np.sqrt(r**2 - d**2)
    arc = 2 * r * (np.pi - np.arctan2(half_chord, d))
    assert both == pytest.approx(2 * np.pi * r + 4 * d, rel=1e-5)
    assert one == pytest.approx(arc + 2 * half_chord, rel=1e-4)
    nothing = np.zeros(len(v), dtype=bool)
    assert np.isnan(tape_girth(v, topo, origin, UP, origin, part=nothing).girth)
