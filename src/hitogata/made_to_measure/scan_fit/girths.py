"""Girths taken on the scan itself, in the fitted body's girth planes.

Each girth's plane is the fitted body's in the scan's pose
(`hitogata.measure.measurements.girth_planes`). The scan's points in that
plane — the crossing points of a scan mesh, or the points of a cloud within
`SLAB` of the plane — that lie against the girth's own skin (their nearest
body vertex is skin the tape may rest on, `tape_skin`) and near the
fitted tape are binned by angle round the fitted tape's centre; in each bin
the points' median radius stands for the bin (so scan noise does not widen
the girth as the outermost points would); the medians joined round the
circle linearly in the angle make a closed curve, sampled finely (so the bins'
chords do not shorten it), and the tape is the convex hull of that
(`hitogata.measure.sections.hull_perimeter`). Where the scan has a hole across
the plane (an inner thigh next to a crotch hole, the side of the chest under
an arm) that leaves more than `MAX_GAP` of the angle without points, the girth
is not measurable on the scan (NaN).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from hitogata.body.model import Body
from hitogata.measure.axes import JointSet
from hitogata.measure.landmarks import body_landmarks
from hitogata.measure.measurements import GIRTHS, girth_planes, tape_skin, tapes
from hitogata.measure.sections import hull_perimeter, plane_basis, section
from hitogata.geometry.topology import topology

SLAB = 0.003  # m: half-thickness of the slab of cloud points taken as lying in a plane
NEAR = 0.02  # m: scan points further than this (radially) from the fitted tape are not that part
BIN_LENGTH = 0.01  # m of the fitted girth per angle bin, between MIN_BINS and MAX_BINS bins
MIN_BINS, MAX_BINS = 12, 72
SAMPLES_PER_BIN = 8  # samples of the median curve per bin, for the hull
MAX_GAP = 30.0  # degrees of angle without scan points: a hole, not a girth


def scan_girths(points: np.ndarray, faces: np.ndarray | None, body: Body, vertices: np.ndarray,
                joints: np.ndarray) -> dict[str, float]:
    """Each girth (m) on the scan points (P, 3) in the body frame (NaN where the scan cannot give it).

    `vertices` (V, 3) and `joints` (B, 3): the fitted body in the scan's pose.
    """
    rest, posed = JointSet(body.rig.names, body.rig.heads), JointSet(body.rig.names, joints)
    marks = body_landmarks(body)
    planes = girth_planes(vertices, marks, rest, posed)
    fitted = tapes(vertices, body.faces, marks, rest, posed, tape_skin(body))
    _, nearest = cKDTree(vertices).query(points)
    topo = topology(faces) if faces is not None else None
    out = {}
    for name in GIRTHS:
        tape = fitted[name]
        if name not in planes or not len(tape.path):  # the armscye is cut at the axilla, not one plane
            out[name] = float("nan")
            continue
        origin, normal, _ = planes[name]
        if topo is not None:
            cut = section(points, topo, origin, normal)
            ends = topo.edges[cut.edges]
            closer = np.where(np.abs((points[ends[:, 0]] - origin) @ normal) <= np.abs((points[ends[:, 1]] - origin)
                                                                                    @ normal), ends[:, 0], ends[:, 1])
            candidates, owner = cut.points, nearest[closer]
        else:
            distance = (points - origin) @ normal
            slab = np.abs(distance) < SLAB
            candidates, owner = points[slab] - distance[slab, None] * normal, nearest[slab]
        skin = tape_skin(body).get(name)
        own = np.ones(len(owner), dtype=bool) if skin is None else skin[owner]
        out[name] = _binned_girth(candidates[own], tape.path, tape.girth, normal)
    return out


def _binned_girth(points: np.ndarray, tape: np.ndarray, girth: float, normal: np.ndarray) -> float:
    """The hull perimeter of per-angle median radii of the points near the fitted tape; NaN across a hole."""
    n, u, v = plane_basis(normal)
    centre = tape.mean(axis=0)
    bins = int(np.clip(girth / BIN_LENGTH, MIN_BINS, MAX_BINS))

    def polar(p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        rel = p - centre
        x, y = rel @ u, rel @ v
        return np.arctan2(y, x), np.hypot(x, y)

    edges = np.linspace(-np.pi, np.pi, bins + 1)
    tape_angle, tape_radius = polar(np.vstack([tape, 0.5 * (tape + np.roll(tape, -1, axis=0))]))
    angle, radius = polar(points)
    tape_bin, point_bin = np.digitize(tape_angle, edges) - 1, np.digitize(angle, edges) - 1
    reach = np.full(bins, np.nan)
    for k in range(bins):  # the fitted tape's radius in each bin (nearest tape sample where none falls in it)
        mine = tape_radius[tape_bin == k]
        if len(mine):
            reach[k] = mine.mean()
    known = np.flatnonzero(np.isfinite(reach))
    centres = 0.5 * (edges[:-1] + edges[1:])
    if len(known) < bins:
        gap = np.abs(np.angle(np.exp(1j * (centres[:, None] - centres[known][None, :]))))
        reach = reach[known][gap.argmin(axis=1)]
    point_bin = np.clip(point_bin, 0, bins - 1)
    near = np.abs(radius - reach[point_bin]) < NEAR
    angle, radius, point_bin = angle[near], radius[near], point_bin[near]
    filled = np.zeros(bins, dtype=bool)
    middle = np.zeros(bins)
    for k in range(bins):
        mine = point_bin == k
        if np.any(mine):
            filled[k], middle[k] = True, np.median(radius[mine])
    if np.count_nonzero(filled) < 3 or _largest_gap(filled) * 360.0 / bins > MAX_GAP:
        return float("nan")
    # The bins' median radii joined round the circle, linearly in the angle: a closed curve, sampled finely.
    known = np.flatnonzero(filled)
    fine = np.linspace(-np.pi, np.pi, bins * SAMPLES_PER_BIN, endpoint=False)
    r = np.interp(fine, centres[known], middle[known], period=2.0 * np.pi)
    ring = centre + r[:, None] * (np.cos(fine)[:, None] * u + np.sin(fine)[:, None] * v)
    return hull_perimeter(ring, n).girth


def _largest_gap(filled: np.ndarray) -> int:
    """The longest run of empty bins, round the circle."""
    if filled.all():
        return 0
    run = best = 0
    for value in np.concatenate([filled, filled]):
        run = 0 if value else run + 1
        best = max(best, run)
    return min(best, len(filled))
