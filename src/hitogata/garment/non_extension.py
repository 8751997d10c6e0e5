"""Lines of non-extension: the skin's directions that do not stretch in a motion, drawn on the body.

Where the skin stretches one way (principal stretch λ1 > 1) and shortens the
other (λ2 < 1), two directions in between keep their length: along
d = cos θ e1 ± sin θ e2 (e1, e2 the principal directions at rest) the stretch
is λ(θ)² = λ1² cos² θ + λ2² sin² θ, which is 1 at

    tan² θ = (λ1² − 1) / (1 − λ2²)        (θ from the direction of most stretch).

Iberall followed these directions over the body through its motions to lay
the inextensible restraint cables of a mobile full-pressure suit along them
(Iberall A. S., "The use of lines of nonextension to improve mobility in
full-pressure suits", Aerospace Medical Research Laboratories,
AMRL-TR-64-118, 1964; "The experimental design of a mobile pressure suit",
J. Basic Engineering 92(2): 251-264, 1970); the skin-strain work for
mechanical counter-pressure suits maps them the same way (Bethke K., MIT
S.M. thesis, 2005; Wessendorf A. M. and Newman D. J., IEEE Trans. Biomed.
Eng. 59(12): 3432-3438, 2012). A tight garment's seams or a stiff fabric's
grain laid along them does not hinder the motion.

Per triangle of the fine skin (`skin.fine_skin`; the posed skin carried
onto it by Loop's stencils, so any surface source will do), from the
principal stretches of `measure.strain` between the rest and one posed frame
(the report takes the frame where the garment zones stretch most:
`garment.fit.peak_frames`), the two directions at rest — where λ2 ≤ 1 ≤ λ1
and λ1 − λ2 ≥ MARGIN (a skin that barely strains has no meaningful
direction; where one principal stretch is 1 the two directions are one). The lines are streamlines of that field on the rest
body: seeded one per SPACING cube of skin that has the field, traced both
ways in steps of STEP (midpoint rule, each point put back onto the nearest
triangle's plane), keeping to the family whose direction is nearest the last
step's, until the field ends, turns by more than MAX_TURN in a step, or the
line is MAX_LENGTH long (or closes on itself round a limb); then, longest
first, each line keeps its longest run at least SPACING/2 from the lines
already kept that run within 30° of it (Jobard and Lefer's evenly spaced
streamlines, 1997; where θ is small the two families nearly coincide and one
line is drawn), when that run is MIN_LENGTH or more.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from hitogata.body.model import Body
from hitogata.measure.strain import skin_strain
from hitogata.skin.fine_skin import body_fine_skin
from hitogata.geometry.normals import face_normals

MARGIN = 0.02  # the principal stretches at least this far apart (λ2 ≤ 1 ≤ λ1)
SPACING = 0.04  # m between seeds, and twice the least distance between lines of one family
STEP = 0.003  # m
MAX_TURN = np.radians(25.0)  # per step
MAX_LENGTH = 0.6  # m, each way from the seed
MIN_LENGTH = 0.05  # m
PARALLEL = np.cos(np.radians(30.0))  # lines closer than SPACING / 2 are kept apart when this parallel


@dataclass(frozen=True)
class NonExtension:
    """Per triangle: the two non-extension directions at rest (F, 2, 3), NaN where the skin has none,
    and their angle θ from the direction of most stretch (F,), radians."""

    directions: np.ndarray
    angle: np.ndarray

    @property
    def present(self) -> np.ndarray:
        """(F,) triangles that have the two directions."""
        return np.isfinite(self.angle)


@dataclass(frozen=True)
class Line:
    """A line of non-extension on the rest surface: points (N, 3), metres, and its family (0: +θ, 1: −θ)."""

    points: np.ndarray
    family: int

    @property
    def length(self) -> float:
        return float(np.linalg.norm(np.diff(self.points, axis=0), axis=1).sum())


def non_extension_directions(rest: np.ndarray, deformed: np.ndarray, faces: np.ndarray,
                             margin: float = MARGIN) -> NonExtension:
    """The rest directions of every triangle whose length `deformed` keeps (`measure.strain`'s F)."""
    strain = skin_strain(rest, deformed, faces)
    l1, l2 = strain.stretch_max, strain.stretch_min
    with np.errstate(invalid="ignore", divide="ignore"):
        present = (l2 <= 1.0) & (l1 >= 1.0) & (l1 - l2 >= margin)
        angle = np.full(len(faces), np.nan)
        angle[present] = np.arctan(np.sqrt((l1[present] ** 2 - 1.0) / (1.0 - l2[present] ** 2)))
    e1 = strain.direction
    e2 = np.cross(face_normals(rest, faces), e1)
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    return NonExtension(np.stack([c * e1 + s * e2, c * e1 - s * e2], axis=1), angle)


class _Field:
    """The direction field on the rest surface, looked up at the triangle whose centroid is nearest."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray, field: NonExtension) -> None:
        self.centroids = vertices[faces].mean(axis=1)
        self.normals = face_normals(vertices, faces)
        self.tree = cKDTree(self.centroids)
        self.reach = np.linalg.norm(vertices[faces] - self.centroids[:, None], axis=2).max(axis=1)
        self.field = field

    def at(self, points: np.ndarray, previous: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """At each point: the face, the direction of either family nearest `previous` (signed to agree),
        and whether it may be followed (on the surface, the field is there and turns by at most MAX_TURN)."""
        distance, face = self.tree.query(points)
        candidates = self.field.directions[face]  # (N, 2, 3)
        dots = np.einsum("nkj,nj->nk", candidates, previous)
        pick = np.nan_to_num(np.abs(dots), nan=-1.0).argmax(axis=1)
        rows = np.arange(len(points))
        chosen = candidates[rows, pick] * np.sign(dots[rows, pick])[:, None]
        ok = (self.field.present[face] & (np.abs(dots[rows, pick]) >= np.cos(MAX_TURN))
              & (distance <= self.reach[face]))
        return face, np.nan_to_num(chosen), ok

    def onto_surface(self, points: np.ndarray, face: np.ndarray) -> np.ndarray:
        offset = np.einsum("nj,nj->n", points - self.centroids[face], self.normals[face])
        return points - offset[:, None] * self.normals[face]


def _trace(field: _Field, start: np.ndarray, direction: np.ndarray, step: float, steps: int) -> list[np.ndarray]:
    """Streamlines from each start point along its initial direction, the live ones advanced together."""
    n = len(start)
    points = np.full((n, steps + 1, 3), np.nan)
    points[:, 0] = start
    ends = np.full(n, steps, int)
    live = np.arange(n)
    p, previous = start.copy(), direction.copy()
    for k in range(steps):
        _, d, ok = field.at(p, previous)
        face, d_mid, ok_mid = field.at(p + 0.5 * step * d, d)
        going = ok & ok_mid
        ends[live[~going]] = k
        live, p, previous = live[going], field.onto_surface(p + step * d_mid, face)[going], d_mid[going]
        if not len(live):
            break
        points[live, k + 1] = p
    return [points[i, : ends[i] + 1] for i in range(n)]


def _seeds(centroids: np.ndarray, present: np.ndarray, spacing: float) -> np.ndarray:
    """One face per `spacing` cube holding faces with the field: the one nearest the cube's centre."""
    faces = np.flatnonzero(present)
    cell = np.floor(centroids[faces] / spacing)
    away = np.linalg.norm(centroids[faces] - (cell + 0.5) * spacing, axis=1)
    order = np.lexsort((away, *cell.T[::-1]))
    _, first = np.unique(cell[order], axis=0, return_index=True)
    return faces[order[first]]


def _tangents(points: np.ndarray) -> np.ndarray:
    """(N, 3) unit tangents of a polyline (central differences, one-sided at the ends)."""
    t = np.gradient(points, axis=0)
    return t / np.maximum(np.linalg.norm(t, axis=1, keepdims=True), 1e-12)


def _without_loops(points: np.ndarray, step: float) -> np.ndarray:
    """The line up to where it first comes back to within half a step of a point it passed long before
    (a line round a limb closes on itself)."""
    pairs = cKDTree(points).query_pairs(0.5 * step, output_type="ndarray")
    far_apart = pairs[np.abs(pairs[:, 1] - pairs[:, 0]) > 3]
    return points if not len(far_apart) else points[: int(far_apart.max(axis=1).min())]


def _longest_free_run(points: np.ndarray, far: np.ndarray) -> np.ndarray:
    """The longest run of consecutive points that are `far` (by length), as a slice of `points`."""
    best, best_len, start = (0, 0), -1.0, None
    seg = np.r_[np.linalg.norm(np.diff(points, axis=0), axis=1), 0.0]
    for i, f in enumerate(np.r_[far, False]):
        if f and start is None:
            start = i
        elif not f and start is not None:
            length = float(seg[start: i - 1].sum())
            if length > best_len:
                best, best_len = (start, i), length
            start = None
    return points[best[0]: best[1]]


def streamlines(vertices: np.ndarray, faces: np.ndarray, field: NonExtension, spacing: float = SPACING,
                step: float = STEP, max_length: float = MAX_LENGTH, min_length: float = MIN_LENGTH) -> list[Line]:
    """Evenly spaced lines of both families of `field` on the surface (`vertices`, `faces`), longest first."""
    if not field.present.any():
        return []
    f = _Field(vertices, faces, field)
    seeds = _seeds(f.centroids, field.present, spacing)
    start = np.repeat(f.centroids[seeds], 4, axis=0)
    d0, d1 = field.directions[seeds, 0], field.directions[seeds, 1]
    initial = np.stack([d0, -d0, d1, -d1], axis=1).reshape(-1, 3)  # row 4 i + 2 family + (0 forward, 1 back)
    traces = _trace(f, start, initial, step, int(np.ceil(max_length / step)))
    candidates = []
    for i in range(len(seeds)):
        for fam in (0, 1):
            forward, back = traces[4 * i + 2 * fam], traces[4 * i + 2 * fam + 1]
            candidates.append(Line(_without_loops(np.concatenate([back[::-1], forward[1:]]), step), fam))
    candidates.sort(key=lambda line: -line.length)
    kept: list[Line] = []
    tree, tangents = None, np.zeros((1, 3))
    kept_tangents: list[np.ndarray] = []
    for line in candidates:
        if line.length < min_length:
            break
        points = line.points
        if tree is not None:
            _, near = tree.query(points, k=8, distance_upper_bound=0.5 * spacing)
            parallel = np.abs(np.einsum("nkj,nj->nk", tangents[near], _tangents(points))) >= PARALLEL
            points = _longest_free_run(points, ~parallel.any(axis=1))
        if len(points) < 2 or Line(points, line.family).length < min_length:
            continue
        kept.append(Line(points, line.family))
        kept_tangents.append(_tangents(points))
        tree = cKDTree(np.concatenate([k.points for k in kept]))
        tangents = np.concatenate([*kept_tangents, np.zeros((1, 3))])  # the last row: no neighbour
    return kept


def non_extension_lines(body: Body, posed: np.ndarray) -> list[Line]:
    """The lines of non-extension on `body`'s rest fine skin for one posed skin (V, 3) of the body."""
    fine = body_fine_skin(body)
    field = non_extension_directions(fine.vertices, fine.carry(posed), fine.faces)
    return streamlines(fine.vertices, fine.faces, field)


def lines_csv(lines_by_motion: dict[str, list[Line]]) -> str:
    """One row per point: motion, line, family, point, x, y, z in millimetres (rest body)."""
    rows = ["motion,line,family,point,x_mm,y_mm,z_mm"]
    for motion, lines in lines_by_motion.items():
        for k, line in enumerate(lines):
            rows += [f"{motion},{k},{line.family},{i},{x * 1e3:.2f},{y * 1e3:.2f},{z * 1e3:.2f}"
                     for i, (x, y, z) in enumerate(line.points)]
    return "\n".join(rows) + "\n"


def lines_json(lines_by_motion: dict[str, list[Line]]) -> dict:
    """Per motion the lines: family, length (mm) and points (mm, rest body)."""
    return {motion: [{"family": line.family, "length_mm": round(line.length * 1e3, 2),
                      "points_mm": np.round(line.points * 1e3, 2).tolist()} for line in lines]
            for motion, lines in lines_by_motion.items()}
