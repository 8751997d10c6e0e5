"""The untangler lifts flat and inverted elements above the volume floor by moving free nodes only."""

import numpy as np

from hitogata.dynamics.untangle import Untangler
from hitogata.fem.verify.box_mesh import box_mesh
from hitogata.volume.quality import signed_volumes

FLOOR = 0.02


def block():
    """A 4 x 4 x 4 cube of 0.1 m cells; the outer nodes held, the 27 inner ones free."""
    points, tets = box_mesh((0.4, 0.4, 0.4), (4, 4, 4))
    inner = np.all((points > 0.05) & (points < 0.35), axis=1)
    return points, tets, inner


def test_a_mesh_above_the_floor_is_returned_unchanged():
    points, tets, inner = block()
    moved = points + 0.01 * np.sin(7.0 * points)  # smooth and right side out
    assert signed_volumes(moved, tets).min() > 0.1 * signed_volumes(points, tets).min()
    np.testing.assert_array_equal(Untangler(points, tets, inner, FLOOR)(moved), moved)


def test_a_crease_of_inverted_elements_is_lifted_by_free_nodes_only():
    points, tets, inner = block()
    x = points.copy()
    centre = np.flatnonzero(np.all(np.isclose(points, 0.2), axis=1))[0]
    neighbour = np.flatnonzero(np.all(np.isclose(points, [0.3, 0.2, 0.2]), axis=1))[0]
    x[centre] += [0.16, 0.0, 0.0]  # past its neighbour: the elements between them fold inside out
    x[neighbour] -= [0.04, 0.0, 0.0]
    rest = signed_volumes(points, tets)
    before = signed_volumes(x, tets) / rest
    assert (before <= 0).sum() >= 4
    untangler = Untangler(points, tets, inner, FLOOR)
    out = untangler(x)
    after = signed_volumes(out, tets) / rest
    assert after.min() >= FLOOR - 1e-9, f"smallest volume ratio {after.min():.4f}"
    np.testing.assert_array_equal(out[~inner], x[~inner])  # held nodes stay where they were
    assert np.abs(out - x).max() < 0.2  # a local repair, within the crease's reach
    assert len(untangler.below_floor(out)) == 0


def test_what_the_linear_programmes_leave_inverted_the_smooth_pass_lifts(monkeypatch):
    """The linear programmes can stall with an element a fraction of a per cent inside out (their linearised
    volumes miss the products of two corners' moves); the smooth penalty on the true volumes then lifts it.
    With no programme run at all, it alone unfolds the crease."""
    from hitogata.dynamics import untangle

    monkeypatch.setattr(untangle, "STEPS", 0)
    points, tets, inner = block()
    x = points.copy()
    centre = np.flatnonzero(np.all(np.isclose(points, 0.2), axis=1))[0]
    x[centre] += [0.13, 0.0, 0.0]  # past the cell's far face: the elements round it fold inside out
    rest = signed_volumes(points, tets)
    assert (signed_volumes(x, tets) <= 0).sum() >= 4
    out = Untangler(points, tets, inner, FLOOR)(x)
    assert (signed_volumes(out, tets) / rest).min() > 0.0
    np.testing.assert_array_equal(out[~inner], x[~inner])
    assert np.abs(out - x).max() < 0.2
