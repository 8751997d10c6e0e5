"""The skin sliding over the fascia (`skin.skin_slide`): a pose's fine skin stretched beyond +100 %
is spread to the skin around it, on the surface as it was and crossing nothing new; a smooth stretch is
left alone."""

from __future__ import annotations

import numpy as np
import pytest

from hitogata.geometry import self_intersections
from hitogata.skin.skin_slide import _svd, slide_posed_skin
from hitogata.measure.strain import skin_strain
from hitogata.geometry.closest import closest_points_on_triangles
from hitogata.skin.fine_skin import body_fine_skinning
from hitogata.posing import poser_for


def test_the_closed_form_svd_is_numpys():
    f = np.random.default_rng(1).normal(size=(500, 3, 2))
    u, s, vt = _svd(f)
    assert np.allclose(s, np.linalg.svd(f, compute_uv=False), atol=1e-12)
    assert np.allclose(np.einsum("fij,fj,fjk->fik", u, s, vt), f, atol=1e-12)
    assert np.allclose(np.einsum("fki,fkj->fij", u, u), np.eye(2), atol=1e-9)


def test_a_smooth_stretch_is_left_alone(female):
    posed = poser_for(female).pose(clinical={"shank_l.flexion": np.radians(60)}, skinning="dqs")
    slid = slide_posed_skin(body_fine_skinning(female), posed.pose, "dqs", female.vertices, posed.vertices,
                            posed.faces)
    for level, start in ((slid.coarse, posed.vertices), (slid.fine, body_fine_skinning(female).surface(posed.pose, "dqs"))):
        assert not level.free.any() and level.iterations == 0 and np.array_equal(level.vertices, start)


@pytest.mark.slow
def test_the_elbows_skin_slides_on_its_surface(female):
    from hitogata.skin.single_pose import elastic_dynamics, elastic_pose

    dynamics = elastic_dynamics(female)
    clinical = {"forearm_l.flexion": np.radians(150)}
    contact = elastic_pose(dynamics, clinical=clinical, contact=True)
    held = elastic_pose(dynamics, clinical=clinical, contact=True, slide=True)
    assert held.slide is not None and contact.slide is None
    rest = body_fine_skinning(female).fine

    def beyond(pose) -> float:
        strain = skin_strain(rest.vertices, pose.fine_vertices(), rest.faces)
        return round(float(strain.rest_area[(strain.stretch_max > 2) | (strain.area_ratio > 2)].sum() * 1e4), 1)

    moved = held.slide.coarse.moved > 0
    tri = contact.vertices[female.faces]
    # every slid vertex lies on the surface it slid on: its distance to the nearest of the faces near it
    near = np.flatnonzero(np.linalg.norm(tri.mean(axis=1) - contact.vertices[moved].mean(axis=0), axis=1) < 0.2)
    off = [np.linalg.norm(closest_points_on_triangles(np.repeat(p[None], len(near), 0), *tri[near].transpose(1, 0, 2))
                          - p, axis=1).min() for p in held.vertices[moved]]
    pairs = {name: set(map(tuple, self_intersections(x, female.faces).tolist()))
             for name, x in (("contact", contact.vertices), ("slid", held.vertices))}
    figures = (beyond(contact), beyond(held), int(held.slide.coarse.free.sum()), int(moved.sum()),
               round(float(held.slide.coarse.moved.max()) * 1e3), len(pairs["slid"] - pairs["contact"]))
    # (cm² beyond +100 % before and after, free vertices, vertices slid, the longest slide mm, new crossing pairs)
    assert figures == (21.3, 0.0, 382, 382, 20, 0)
    assert max(off) < 1e-8
    # the rest of the skin is the contact's (two solves of one pose agree to round-off)
    assert np.abs(held.vertices[~moved] - contact.vertices[~moved]).max() < 1e-8

