"""The extreme poses (`hitogata.skeleton.extreme_poses`) held by the elastic body with its
self-contact resolved and its skin slid over the fascia (`elastic_pose(..., contact=True, slide=True)`),
on both default bodies: the skin passes nowhere through itself, no vertex lies inside another part, no
element inverts, the body keeps its volume, the flexor side of elbow and knee shortens (its creases
fold: `contact.crease_tether`), and no fine triangle is stretched beyond +100 % (the skin slides over the
fascia, and its fine skin on its own: `skin.skin_slide`)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import cKDTree

from hitogata.skin.single_pose import elastic_dynamics, elastic_pose
from hitogata.geometry import enclosed_volume, self_intersections
from hitogata.measure import measure
from hitogata.measure.body_lines import body_lines
from hitogata.measure.strain import skin_strain
from hitogata.skeleton.extreme_poses import extreme_poses
from hitogata.geometry.closest import closest_points_on_triangles
from hitogata.skin.fine_skin import body_fine_skinning

pytestmark = pytest.mark.slow
# % against rest: the tissue a contact presses aside swells round it (docs/elastic.md); a crease folded
# (`contact.crease_tether`) gives its volume back as a swelling of the free skin round it; the slide moves
# skin within the surface, which changes the faceted surface's volume by up to 0.3 %
VOLUME = {
    "female": {"elbow 150°": -0.191, "knee 135°": -0.143, "hip flexion 120°": -0.517, "seated 90/90": -0.508,
               "hip adduction 30°": 0.074, "shoulder flexion 180°": 0.394, "shoulder abduction 170°": 0.283,
               "neck flexion 45°": -0.005, "trunk flexion 80°": -0.044, "trunk rotation 45°": -0.121},
    "male": {"elbow 150°": -0.051, "knee 135°": -0.181, "hip flexion 120°": -0.421, "seated 90/90": -0.547,
             "hip adduction 30°": 0.026, "shoulder flexion 180°": -0.383, "shoulder abduction 170°": -0.335,
             "neck flexion 45°": -0.008, "trunk flexion 80°": -0.405, "trunk rotation 45°": -0.101},
}
# the fine skin's own slide where the coarse skin's left some beyond +100 %: (cm² beyond +100 % before it,
# its free vertices, the vertices it slid, the longest slide mm, new crossing pairs of fine triangles); the
# female knee 135° left 2.5 cm² to it with 200 plain steps, none with the converged ones (decision 0062)
FINE_SLID = {
    "female": {"seated 90/90": (2.7, 3967, 3967, 6, 0),
               "shoulder flexion 180°": (3.3, 6210, 6210, 5, 0), "shoulder abduction 170°": (1.9, 5937, 5937, 3, 0)},
    "male": {"knee 135°": (0.3, 1848, 1848, 5, 0), "hip flexion 120°": (32.2, 5534, 5534, 28, 0),
             "hip adduction 30°": (1.0, 3773, 3773, 3, 0),
             "shoulder flexion 180°": (7.8, 5168, 5168, 6, 0), "shoulder abduction 170°": (2.5, 4644, 4644, 3, 0)},
}
VOLUME_TOLERANCE = 0.1  # percentage points (see the volume test)
# new crossing pairs of fine triangles the slide may leave: none
FINE_CROSSING: dict[str, dict[str, int]] = {"female": {}, "male": {}}
# % change of length of the flexor side's line on the fine skin (docs/measurements.md, "Skin stretch on lines"):
# without the creases' tether the back of the knee lengthened at 135° (+3 % on both bodies)
FLEXOR = {
    "female": {("elbow 150°", "elbow_anterior"): -23.0, ("knee 135°", "knee_posterior"): -29.5,
               ("seated 90/90", "knee_posterior"): -43.8},
    "male": {("elbow 150°", "elbow_anterior"): -26.7, ("knee 135°", "knee_posterior"): -19.8,
             ("seated 90/90", "knee_posterior"): -33.2},
}


@pytest.fixture(scope="module", params=["female", "male"])
def held(request):
    """The body's name, its rest skin and every extreme pose held with contact."""
    body = request.getfixturevalue(request.param)
    dynamics = elastic_dynamics(body)
    poses = {name: elastic_pose(dynamics, clinical=clinical, contact=True, slide=True)
             for name, clinical in extreme_poses(dynamics.poser.skeleton).items()}
    return request.param, body, poses


def test_the_skin_stays_whole_and_the_body_keeps_its_volume(held):
    sex, body, poses = held
    rest_pairs = set(map(tuple, self_intersections(body.vertices, body.faces).tolist()))
    rest_volume = enclosed_volume(body.vertices, body.faces)
    figures = {}
    for name, pose in poses.items():
        crossing = set(map(tuple, self_intersections(pose.vertices, body.faces).tolist())) - rest_pairs
        inside = pose.penetrations
        figures[name] = (len(crossing), len(inside), round(inside.deepest * 1e3, 1), pose.quality.inverted,
                         round((enclosed_volume(pose.vertices, body.faces) / rest_volume - 1) * 100, 3))
    # (new crossing pairs beyond the rest body's, vertices inside another part, the deepest mm, inverted
    # elements, enclosed volume against rest %): the issue asks 0, ≤ 2 mm, 0, within 1 %. (The male hip flexion's
    # 3 vertices tucked into the groin under the pelvis's open rim, 14-17 mm "inside" by the signed distance
    # alone, read a winding number of 0.62-0.98: between two sheets of skin, not inside.)
    assert {name: f[:4] for name, f in figures.items()} == dict.fromkeys(poses, (0, 0, 0.0, 0))
    # within 1 % of rest, as asked, and near the figures above: to 0.1 points, the margin another machine's
    # round-off took when the quasi-statics' answer hung on it (0.054 points at the male seated pose on a fresh
    # clone); it no longer does (decision 0061)
    assert all(abs(f[4]) < 1.0 for f in figures.values())
    assert {name: f[4] for name, f in figures.items()} == pytest.approx(VOLUME[sex], abs=VOLUME_TOLERANCE)


def test_the_fine_skin_is_stretched_like_skin(held):
    sex, body, poses = held
    rest = body_fine_skinning(body).fine
    figures = {}
    for name, pose in poses.items():
        strain = skin_strain(rest.vertices, pose.fine_vertices(), rest.faces)
        over = (strain.stretch_max > 2) | (strain.area_ratio > 2)
        figures[name] = round(float(strain.rest_area[over].sum() * 1e4), 1)
    # cm² of fine skin stretched beyond +100 % (length or area): none. Without the slide 5-131 cm² at 8 of 10
    # poses; after the coarse skin's slide alone 0.5-38 cm² at 7 of the 20 (the armpit's hollow overhead, the
    # male groin), which the fine skin's own slide takes out (docs/elastic.md)
    assert figures == dict.fromkeys(poses, 0.0)


def test_the_fine_skin_slides_on_its_own_surface(held):
    """Where the coarse skin's slide stops (its triangles may turn no further), the fine skin slides on its own
    surface: every slid fine vertex on the fine skin as the coarse skin carried it, no fine triangle crossing
    another where none did, the rest of the fine skin as carried."""
    sex, body, poses = held
    fs = body_fine_skinning(body)
    figures = {}
    for name, pose in poses.items():
        fine = pose.slide.fine
        carried = fs.surface(pose.posed.pose, "dqs", pose.vertices)
        assert np.array_equal(fine.vertices[fine.moved == 0], carried[fine.moved == 0])
        if not fine.free.any():
            continue
        moved = fine.moved > 0
        # the fine faces within 5 cm of the slid skin, as carried and as slid
        centroids = carried[fs.fine.faces].mean(axis=1)
        near = np.flatnonzero(cKDTree(carried[moved]).query(centroids, distance_upper_bound=0.05)[0] < np.inf)
        tri = carried[fs.fine.faces[near]]
        off = [np.linalg.norm(closest_points_on_triangles(np.repeat(p[None], len(near), 0), *tri.transpose(1, 0, 2))
                              - p, axis=1).min() for p in fine.vertices[moved][::100]]
        assert max(off) < 1e-8
        pairs = [set(map(tuple, self_intersections(x, fs.fine.faces[near]).tolist())) for x in (carried, fine.vertices)]
        strain = skin_strain(fs.fine.vertices, carried, fs.fine.faces)
        beyond = round(float(strain.rest_area[(strain.stretch_max > 2) | (strain.area_ratio > 2)].sum() * 1e4), 1)
        figures[name] = (beyond, int(fine.free.sum()), int(moved.sum()), round(float(fine.moved.max()) * 1e3),
                         len(pairs[1] - pairs[0]))
    # what the fine skin's own slide does, wherever it runs: every free vertex slides, no fine triangle crosses
    # another where the carried skin's did not, no slide longer than 4 cm
    for name, (_, free, moved, longest, crossing) in figures.items():
        assert free == moved and longest <= 40 and crossing <= FINE_CROSSING[sex].get(name, 0), (name, figures[name])
    # where it runs and how much: the coarse skin's slide stops where its contact stops it; the poses above
    # slide on every machine, each within a factor 2 of the figures above (round-off moved the male seated
    # pose's by a factor 1.6 between machines while the quasi-statics' answer hung on it: decision 0061)
    assert set(FINE_SLID[sex]) <= set(figures)
    for name, (beyond, free, *_) in FINE_SLID[sex].items():
        got = figures[name]
        assert beyond / 2 <= got[0] <= beyond * 2 + 1.0 and free / 2 <= got[1] <= free * 2, (name, got)


def test_the_flexor_side_of_elbow_and_knee_shortens(held):
    sex, body, poses = held
    fine = body_fine_skinning(body)
    lines = body_lines(body, fine.fine.vertices, fine.fine.faces)
    change = {(pose, line): round((lines[line].length(poses[pose].fine_vertices())
                                   / lines[line].length(fine.fine.vertices) - 1) * 100, 1)
              for pose, line in FLEXOR[sex]}
    assert all(c < 0 for c in change.values())
    # to 1.5 points (5 mm of a 30-40 cm line): the line crosses the crease, where the barrier holds skin pairs
    # apart at its Newton tolerance (0.5 mm) and another machine's round-off holds others
    assert change == pytest.approx(FLEXOR[sex], abs=1.5)


def test_the_knee_girth_is_defined_standing_and_sitting(held):
    """The knee girth's plane bisects femur and tibia: at 90° it cuts the knee (`measure.knee_along_limbs`),
    and the tape goes round it on the held skin (skinned and elastic both)."""
    _, body, poses = held
    seated = poses["seated 90/90"]
    for vertices in (body.vertices, seated.skinned, seated.vertices):
        assert np.isfinite(measure(body, vertices, seated.posed.rig_joints if vertices is not body.vertices
                                   else body.rig.heads).knee_girth)
