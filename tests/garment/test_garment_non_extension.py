"""Lines of non-extension (`garment.non_extension`) against exact answers, and pinned on a body's squat.

A sheet stretched 20 % along x and shortened 10 % along y keeps the length of the directions at
±θ from x with tan² θ = (1.2² − 1) / (1 − 0.9²) (θ = 56.69°); a cylinder twisted by τ (simple shear
γ = r τ along its circumference) keeps its circles and the helices at atan(2 / γ) from them
(|F d|² = 1 + 2 γ sin φ cos φ + γ² sin² φ = 1).
"""

from __future__ import annotations

import csv
import io
import json

import numpy as np
import pytest
from scipy.spatial import cKDTree

from hitogata.motion.scenario import load_scenario, shipped_scenarios
from hitogata.garment.ease import skinned_surface
from hitogata.garment.non_extension import (
    Line, lines_csv, lines_json, non_extension_directions, non_extension_lines, streamlines,
)
from hitogata.motion.clip import scenario_clip
from hitogata.posing import poser_for
from hitogata.garment.stretch import garment_zones
from hitogata.skin.fine_skin import body_fine_skin

SHEET_ANGLE = np.degrees(np.arctan(np.sqrt((1.2**2 - 1) / (1 - 0.9**2))))


def grid(n: int, size: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """An n × n grid of points in [0, size]², and its triangles (two per cell, counter-clockwise)."""
    x, y = np.meshgrid(np.linspace(0, size, n), np.linspace(0, size, n))
    idx = np.arange(n * n).reshape(n, n)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    return x.ravel(), y.ravel(), np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])


def test_a_stretched_sheet_keeps_the_length_of_the_exact_directions():
    x, y, faces = grid(60, 0.3)
    rest = np.stack([x, y, np.zeros_like(x)], axis=1)
    field = non_extension_directions(rest, rest * [1.2, 0.9, 1.0], faces)
    assert field.present.all()
    angles = np.degrees(np.arctan2(field.directions[..., 1], field.directions[..., 0])) % 180
    assert SHEET_ANGLE == pytest.approx(56.6899, abs=1e-4)
    assert np.abs(angles[:, 0] - SHEET_ANGLE).max() < 1e-6 and np.abs(angles[:, 1] - (180 - SHEET_ANGLE)).max() < 1e-6
    lines = streamlines(rest, faces, field)
    assert {line.family for line in lines} == {0, 1}
    for line in lines:  # straight, at the exact angle, from edge to edge
        d = line.points[-1] - line.points[0]
        along = np.degrees(np.arctan2(d[1], d[0])) % 180
        assert abs(along - (SHEET_ANGLE if line.family == 0 else 180 - SHEET_ANGLE)) < 0.1
        rel, unit = line.points - line.points[0], d / np.linalg.norm(d)
        off = rel[:, 0] * unit[1] - rel[:, 1] * unit[0]
        assert np.abs(off).max() < 1e-9
    assert max(line.length for line in lines) == pytest.approx(0.3 / np.sin(np.radians(SHEET_ANGLE)), abs=0.01)


def tube(radius: float, height: float, around: int, rings: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A closed tube along +Y: each vertex's angle and height, and its triangles (normals outward)."""
    turn, y = np.meshgrid(np.linspace(0, 2 * np.pi, around, endpoint=False), np.linspace(0, height, rings))
    idx = np.arange(rings * around).reshape(rings, around)
    nxt = np.roll(idx, -1, axis=1)
    a, b, c, d = idx[:-1].ravel(), nxt[:-1].ravel(), nxt[1:].ravel(), idx[1:].ravel()
    return turn.ravel(), y.ravel(), np.concatenate([np.stack([a, c, b], 1), np.stack([a, d, c], 1)])


def test_a_twisted_cylinder_keeps_its_circles_and_helices():
    r, tau = 0.05, 2.0  # m, rad/m: γ = r τ = 0.1
    turn, y, faces = tube(r, 0.2, 720, 200)

    def surface(angle: np.ndarray) -> np.ndarray:
        return np.stack([r * np.cos(angle), y, r * np.sin(angle)], axis=1)

    rest = surface(turn)
    field = non_extension_directions(rest, surface(turn + tau * y), faces)
    assert field.present.all()
    centre = rest[faces].mean(axis=1)
    circle = np.stack([-centre[:, 2], np.zeros(len(centre)), centre[:, 0]], axis=1)
    circle /= np.linalg.norm(circle, axis=1, keepdims=True)
    along = np.einsum("fkj,fj->fk", field.directions, circle)
    angles = np.degrees(np.arctan2(field.directions[..., 1], along)) % 180
    helix = np.degrees(np.arctan2(2.0, -r * tau)) % 180  # tan φ = −2 / γ: 92.86°
    assert helix == pytest.approx(92.8624, abs=1e-4)
    circles = np.minimum(angles, 180 - angles).min(axis=1)
    helices = np.abs(angles - helix).min(axis=1)
    assert circles.max() < 0.1 and helices.max() < 0.1
    lines = streamlines(rest, faces, field)
    round_ = [line for line in lines if np.ptp(line.points[:, 1]) < 1e-3]
    assert round_ and all(line.length == pytest.approx(2 * np.pi * r, rel=0.05) for line in round_)


def test_a_rigid_motion_has_no_lines():
    x, y, faces = grid(20, 0.2)
    rest = np.stack([x, y, 0.1 * x * y], axis=1)
    turn = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    field = non_extension_directions(rest, rest @ turn.T + 1.0, faces)
    assert not field.present.any() and streamlines(rest, faces, field) == []


def test_the_tables_hold_the_lines_in_millimetres():
    line = Line(np.array([[0.0, 1.0, 0.0], [0.003, 1.004, 0.0]]), 1)
    rows = list(csv.DictReader(io.StringIO(lines_csv({"sit": [line]}))))
    assert [(r["motion"], r["line"], r["family"], r["point"]) for r in rows] == [("sit", "0", "1", "0"),
                                                                                ("sit", "0", "1", "1")]
    assert [float(rows[1][k]) for k in ("x_mm", "y_mm", "z_mm")] == [3.0, 1004.0, 0.0]
    table = json.loads(json.dumps(lines_json({"sit": [line]})))
    assert table == {"sit": [{"family": 1, "length_mm": 5.0, "points_mm": [[0.0, 1000.0, 0.0], [3.0, 1004.0, 0.0]]}]}


def test_the_deep_squat_draws_lines_over_the_knee(female):
    """Pinned: the default female's deep squat held (1.5 s), DQS; the lines on her rest fine skin. The knee
    stretches along the leg most, so its lines run nearer round the leg than along it."""
    clip = scenario_clip(load_scenario(shipped_scenarios()["mobility_deep_squat"]), poser_for(female))
    frame = int(np.argmin(np.abs(clip.times - 1.5)))
    posed = skinned_surface(female)(clip.angles[[frame]], clip.root[[frame]])[0]
    lines = non_extension_lines(female, posed)
    fine = body_fine_skin(female)
    knee = np.zeros(len(female.faces), bool)
    knee[garment_zones(female)[0]["knee"]] = True
    tree = cKDTree(fine.vertices[fine.faces].mean(axis=1))
    lengthwise = garment_zones(female)[1]
    inside, lengths, along = 0, 0.0, 0.0
    for line in lines:
        middle, step = 0.5 * (line.points[1:] + line.points[:-1]), np.diff(line.points, axis=0)
        face = fine.parent[tree.query(middle)[1]]
        on = knee[face]
        inside += bool(on.any())
        lengths += float(np.linalg.norm(step, axis=1)[on].sum())
        along += float(np.abs(np.einsum("ij,ij->i", step[on], lengthwise[face[on]])).sum())
    assert (len(lines), round(sum(line.length for line in lines), 1)) == (370, 43.9)
    assert (inside, round(lengths, 2), round(along / lengths, 2)) == (17, 1.48, 0.44)  # mean |cos| to the leg < 0.5
