"""Laplace's law on a garment's cross-section: P = T κ, κ the local curvature of the tape's path.

A stretched tubular fabric lying round a convex section presses on it with
P = T κ (T: tension per unit width, N/m; κ: curvature of the section curve in
the girth plane, 1/m). The fabric bridges hollows as a tape does, so its path
is the section's convex hull; over a bridge κ = 0 and nothing presses.

Curvature of a polygon: its turning angle Θ(s) against arc length s, made
piecewise linear (each vertex's turn spread between the midpoints of its two
edges, at most SPREAD median edges: exact on a regular polygon), then κ(s) = (Θ(s + h) − Θ(s − h)) / 2h —
the mean curvature over a window of 2h. ∮ κ ds = 2π holds exactly, so the
pressures balance the tension: ∮ P ds = 2π T. The window smooths the mesh's
facets; it must be small against the distance over which the curvature changes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.errors import HitogataError
from hitogata.measure.sections import plane_basis

WINDOW = 0.015  # m, half-width h on a body (its mesh edges are ~1 cm)
SPACING = 0.002  # m between the samples of a profile
SPREAD = 2.0  # a vertex's turn spreads over at most this many median edge lengths each side


@dataclass(frozen=True)
class CurvatureProfile:
    """Samples along a closed convex path: positions (S, 3), arc length (S,) m, curvature (S,) 1/m."""

    points: np.ndarray
    arc: np.ndarray
    curvature: np.ndarray
    length: float


def polygon_curvature(path: np.ndarray, normal: np.ndarray, window: float = WINDOW,
                      spacing: float = SPACING) -> CurvatureProfile:
    """The windowed curvature of a closed convex polygon (H, 3) lying in the plane with `normal`."""
    path = np.asarray(path, dtype=float)
    if len(path) < 3 or not np.isfinite(path).all():
        raise HitogataError(f"section path of {len(path)} points: allowed a closed polygon of 3 or more finite points")
    if not window > 0:
        raise HitogataError(f"curvature window {window!r} m: allowed a length > 0")
    _, u, v = plane_basis(normal)
    flat = np.stack([path @ u, path @ v], axis=1)
    if _signed_area(flat) < 0:
        flat, path = flat[::-1], path[::-1]
    edges = np.roll(flat, -1, axis=0) - flat  # edge i: vertex i → i + 1
    lengths = np.linalg.norm(edges, axis=1)
    keep = lengths > 1e-12
    if keep.sum() < 3:
        raise HitogataError("section path: fewer than 3 distinct points; allowed a closed polygon")
    flat, path = flat[keep], path[keep]
    edges = np.roll(flat, -1, axis=0) - flat
    lengths = np.linalg.norm(edges, axis=1)
    heading = np.arctan2(edges[:, 1], edges[:, 0])
    turn = np.mod(heading - np.roll(heading, 1) + np.pi, 2 * np.pi) - np.pi  # at vertex i, from edge i−1 to i
    start = np.concatenate([[0.0], np.cumsum(lengths)[:-1]])  # arc length of vertex i
    total = float(lengths.sum())
    # Θ rises by vertex i's turn from s_i − a_i to s_i + b_i: half of each edge beside it, but no
    # more than SPREAD median edges, so a long edge bridging a hollow stays straight (κ = 0).
    cap = SPREAD * float(np.median(lengths))
    before, after = np.minimum(0.5 * np.roll(lengths, 1), cap), np.minimum(0.5 * lengths, cap)
    cumulative = np.cumsum(turn)
    knots = np.ravel(np.column_stack([start - before, start + after]))
    values = np.ravel(np.column_stack([cumulative - turn, cumulative]))
    winding = float(cumulative[-1])

    def big_theta(s: np.ndarray) -> np.ndarray:
        laps = np.floor((s - knots[0]) / total)
        local = s - laps * total
        return np.interp(local, np.append(knots, knots[0] + total), np.append(values, values[0] + winding)) \
            + laps * winding

    count = max(int(np.ceil(total / spacing)), 16)
    arc = np.arange(count) * (total / count)
    curvature = (big_theta(arc + window) - big_theta(arc - window)) / (2.0 * window)
    k = np.clip(np.searchsorted(start, arc, side="right") - 1, 0, len(start) - 1)
    along = ((arc - start[k]) / lengths[k])[:, None]
    points = path[k] + along * (np.roll(path, -1, axis=0)[k] - path[k])
    return CurvatureProfile(points, arc, curvature, total)


def _signed_area(flat: np.ndarray) -> float:
    x, y = flat[:, 0], flat[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
