"""Self-contact as a barrier problem (`geometry.barrier_contact`, IPC): two spheres driven through each
other along a path (the body's elbow and knee: tests/skin/test_self_contact.py)."""

from __future__ import annotations

import numpy as np
import pytest

from hitogata.geometry import enclosed_volume, self_intersections
from hitogata.geometry.barrier_contact import BARRIER_DEFAULTS, barrier_resolve, contact_regions
from hitogata.geometry.contact import SelfContact
from samples import two_spheres

RADIUS = 0.05


def test_spheres_driven_together_meet_flattened_and_keep_their_volume():
    apart, faces, groups = two_spheres(RADIUS, 3)
    v = apart(0.0)[groups == 0]  # one sphere's vertices
    test = SelfContact(apart(0.2), faces, groups)
    path = [apart(d) for d in (0.2, 0.15, 0.12, 0.1, 0.09)]  # the target: 10 mm of overlap
    # each step's unknowns: the skin that may meet by then (within 20 mm of the other sphere: none at 150 mm
    # apart, the poles' at 120), each holding the last
    regions = contact_regions(path[1:], test)
    assert regions.sum(axis=1).tolist() == [0, 74, 370, 470] and (regions[3] >= regions[2]).all()
    result = barrier_resolve(path, test)
    x = result.vertices
    assert result.iterations == [0, 0, 4, 4]  # the two first steps meet nothing: the target as it is
    assert len(self_intersections(x, faces)) == 0 and len(test.penetrations(x)) == 0
    assert 0.0 < result.min_distance < BARRIER_DEFAULTS.dhat
    assert result.min_distance == pytest.approx(1.829e-3, rel=1e-3)
    # flattened against each other: the poles that met (each 10 mm inside the other sphere in the
    # target) pushed back ~5 mm each, to either side of the mid-plane z = 45 mm
    top, bottom = x[np.argmax(v[:, 2]), 2], x[len(v) + np.argmin(v[:, 2]), 2]
    assert (round(top * 1e3, 2), round(bottom * 1e3, 2)) == (43.74, 45.68)
    # the volume the overlap held (counted twice by the target) is kept: the skin round the contact swells by
    # what the contact presses in, to 0.005 % of the target's (53 mm³ of 1.05 L; the Newton steps stop at 0.5 mm)
    assert enclosed_volume(x, faces) / enclosed_volume(path[-1], faces) - 1 == pytest.approx(-5.03e-5, abs=1e-6)
    # only the skin near the contact moves: the far poles stay where the target has them
    moved = np.linalg.norm(x - path[-1], axis=1) > 1e-9
    assert moved.sum() == 470 and not moved[np.argmin(v[:, 2])] and not moved[len(v) + np.argmax(v[:, 2])]

