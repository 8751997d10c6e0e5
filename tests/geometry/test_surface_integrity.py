"""surface_integrity: folds, crossings, speed, floor and jumps of a moving surface, on shapes with known answers."""

import numpy as np
import pytest
import trimesh

from hitogata.geometry import self_intersections, surface_integrity
from hitogata.geometry.broad_phase import SPARSE_ACTIVE, box_pairs
from hitogata.geometry.integrity import _crossing_pairs


def sweep_and_prune(lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The reference broad phase: boxes sorted by their low x; each box against those starting within its
    x extent, then the overlap on all axes. All pairs (i < j)."""
    order = np.argsort(lo[:, 0], kind="stable")
    start = lo[order, 0]
    first = np.arange(len(order)) + 1
    last = np.searchsorted(start, hi[order, 0], side="right")
    count = np.maximum(last - first, 0)
    a = np.repeat(np.arange(len(order)), count)
    b = a + 1 + np.arange(len(a)) - np.repeat(np.cumsum(count) - count, count)
    i, j = order[a], order[b]
    keep = np.all((lo[i] <= hi[j]) & (lo[j] <= hi[i]), axis=1)
    i, j = i[keep], j[keep]
    return np.minimum(i, j), np.maximum(i, j)


def grid(n: int = 6, size: float = 0.1) -> tuple[np.ndarray, np.ndarray]:
    """A flat n x n vertex sheet in the xz plane at height 0.5 m, two triangles per square."""
    u = np.linspace(0.0, size, n)
    x, z = np.meshgrid(u, u, indexing="ij")
    vertices = np.stack([x.ravel(), np.full(n * n, 0.5), z.ravel()], axis=1)
    faces = []
    for i in range(n - 1):
        for j in range(n - 1):
            a, b, c, d = i * n + j, (i + 1) * n + j, (i + 1) * n + j + 1, i * n + j + 1
            faces += [(a, b, c), (a, c, d)]
    return vertices, np.array(faces)


def test_a_still_surface_is_whole():
    v, f = grid()
    r = surface_integrity(v, f, np.stack([v, v, v]), np.array([0.0, 0.1, 0.2]), np.stack([v, v, v]))
    w = r.worst()
    assert w["new_folds"] == w["new_self_intersections"] == w["below_floor"] == 0
    assert w["largest_speed_m_s"] == w["largest_elastic_m"] == w["largest_elastic_jump_m"] == 0.0


def test_a_vertex_pulled_through_the_sheet_folds_it_and_jumps():
    v, f = grid()
    moved = v.copy()
    inner = 2 * 6 + 2  # an interior vertex: its 6 triangles turn over when it goes far past its neighbours
    moved[inner] += [0.05, 0.0, 0.05]  # dragged across its neighbours, in the sheet's plane
    r = surface_integrity(v, f, np.stack([v, moved]), np.array([0.0, 0.04]), np.stack([v, v]))
    assert r.new_folds[0] == 0 and r.new_folds[1] > 0
    assert r.folds_beyond_reference[1] == r.new_folds[1]
    assert r.speed[1] == pytest.approx(np.hypot(0.05, 0.05) / 0.04)
    assert r.jump[1] == pytest.approx(np.hypot(0.05, 0.05)) and r.displacement[1] == pytest.approx(np.hypot(0.05, 0.05))
    # the same frames as the reference: nothing beyond it
    same = surface_integrity(v, f, np.stack([v, moved]), np.array([0.0, 0.04]), np.stack([v, moved]))
    assert same.folds_beyond_reference[1] == 0 and same.intersections_beyond_reference[1] == 0
    assert same.new_folds[1] == r.new_folds[1] and same.jump.max() == 0.0


def test_two_sheets_pushed_through_each_other_cross():
    v, f = grid()
    top = v + [0.02, 0.03, 0.02]
    vertices = np.concatenate([v, top])
    faces = np.concatenate([f, f + len(v)])
    through = vertices.copy()
    through[len(v):, 1] = 0.5 + 0.03 * np.sin(np.linspace(0, 9, len(v)))  # wavy, through the lower sheet
    r = surface_integrity(vertices, faces, np.stack([vertices, through]), np.array([0.0, 1.0]))
    expected = len(self_intersections(through, faces))
    assert expected > 0 and r.new_intersections[1] == expected and r.new_intersections[0] == 0
    # with the reference crossing the same way, none is beyond it
    ref = surface_integrity(vertices, faces, np.stack([vertices, through]), np.array([0.0, 1.0]),
                            np.stack([vertices, through]))
    assert ref.intersections_beyond_reference[1] == 0


def test_below_the_floor_counts_vertices_lower_than_a_millimetre():
    v, f = grid()
    low = v.copy()
    low[:, 1] = 0.0
    low[:3, 1] = -0.002
    low[3, 1] = -0.0005  # within the tolerance
    r = surface_integrity(v, f, np.stack([v, low]))
    assert list(r.below_floor) == [0, 3] and r.lowest[1] == pytest.approx(-0.002)


def test_broad_phase_finds_every_overlapping_box_pair_of_the_body(female):
    tri = female.vertices[female.faces]
    lo, hi = tri.min(axis=1), tri.max(axis=1)
    i, j = box_pairs(lo, hi)
    a, b = sweep_and_prune(lo, hi)
    assert set(zip(i.tolist(), j.tolist())) == set(zip(a.tolist(), b.tolist()))
    height = female.vertices[female.faces][:, :, 1].mean(axis=1)
    # a broad share of active boxes, and a few (under SPARSE_ACTIVE: only the boxes in their bounds looked at)
    for active in (height > 1.0, (height > 1.0) & (height < 1.02)):
        i, j = box_pairs(lo, hi, active)
        expected = {(p, q) for p, q in zip(a.tolist(), b.tolist()) if active[p] or active[q]}
        assert set(zip(i.tolist(), j.tolist())) == expected and len(expected) > 1000


def test_crossings_of_a_few_active_faces_are_those_of_all_faces_they_are_in():
    """The crossing pairs with an active face, found among the faces in the active ones' bounds only (a
    limiter's round), are those found among all faces: two spheres overlapping, a band of one active."""
    sphere = trimesh.creation.icosphere(subdivisions=4, radius=0.05)
    v, f = sphere.vertices, sphere.faces
    x, faces = np.concatenate([v, v + [0.0, 0.0, 0.09]]), np.concatenate([f, f + len(v)])
    everywhere = _crossing_pairs(x, faces)
    height = x[faces][:, :, 0].mean(axis=1)
    active = (np.arange(len(faces)) >= len(f)) & (np.abs(height) < 0.01)
    assert active.mean() < SPARSE_ACTIVE
    expected = {(p, q) for p, q in everywhere.tolist() if active[p] or active[q]}
    assert set(map(tuple, _crossing_pairs(x, faces, active).tolist())) == expected and len(expected) == 62


def test_a_torn_run_warns_in_one_line_before_its_figures():
    from hitogata.simulation.run import Summary, surface_problems

    v, f = grid()
    torn = v.copy()
    torn[:5, 1] = -0.24  # a row thrown 240 mm below the floor in one 40 ms frame
    surface = surface_integrity(v, f, np.stack([v, torn]), np.array([0.0, 0.04]), np.stack([v, v])).worst()
    problems = surface_problems(surface)
    assert any("below the floor" in p for p in problems) and any("jump of 740 mm" in p for p in problems)
    figures = {"body": "b", "model": "m", "frequencies_hz": [1.0], "damping_ratios": [0.2], "largest_elastic_mm": 740.0,
               "largest_elastic_time_s": 0.04, "largest_elastic_part": "shank_r", "largest_total_mm": 740.0,
               "region_motion_mm": {}, "inverted_max": 0, "volume_change_max_percent": 0.0,
               "seconds": {"model": 0.0, "simulation": 0.0, "files": 0.0}, "surface": surface,
               "held_back_mm": 0.0, "held_back_time_s": 0.0, "held_back_vertices": 0}
    lines = Summary("t", figures).text().splitlines()
    warnings = [k for k, line in enumerate(lines) if "WARNING" in line]
    assert len(warnings) == 1 and "largest skin displacement" in lines[warnings[0] + 1]
    assert "not results" in lines[warnings[0]]


def test_the_offset_limiter_holds_back_only_what_crosses_or_folds():
    """Two sheets 30 mm apart; an offset pushes a patch of the upper one 50 mm down (through the lower
    sheet) and drags one vertex far across its neighbours (a fold): the limiter keeps the surface whole,
    holding back near the offending skin only; holding back crossings alone, no more than that."""
    from hitogata.geometry.offset_limit import OffsetLimiter

    v, f = grid(n=11, size=0.2)
    top = v + [0.0, 0.03, 0.0]
    vertices, faces = np.concatenate([v, top]), np.concatenate([f, f + len(v)])
    offset = np.zeros_like(vertices)
    centre = len(v) + 5 * 11 + 5
    patch = len(v) + np.flatnonzero(np.linalg.norm(v[:, [0, 2]] - v[5 * 11 + 5, [0, 2]], axis=1) < 0.03)
    offset[patch, 1] = -0.05
    dragged = len(v) + 1 * 11 + 8  # far from the patch
    offset[dragged] = [0.06, 0.0, 0.0]
    limiter = OffsetLimiter(vertices, faces)
    assert len(self_intersections(vertices + offset, faces)) > 0
    surface, kept = limiter(vertices, offset)
    assert len(self_intersections(surface, faces)) == 0
    assert kept[centre] < 0.7 and kept[dragged] < 1.0  # the push and the drag held back
    # a hold fades out over 40 mm of surface from the offending triangles' corners
    far = (np.linalg.norm(vertices - vertices[centre], axis=1) > 0.11) & (
        np.linalg.norm(vertices - vertices[dragged], axis=1) > 0.11)
    assert far.sum() == 41 and np.all(kept[far] == 1.0)
    crossing_only, kept_more = limiter.hold_crossings(vertices, offset)  # crossings only: holds no more
    assert len(self_intersections(crossing_only, faces)) == 0
    assert np.all(kept_more >= kept) and kept_more[centre] < 0.7
