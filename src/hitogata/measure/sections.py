"""Planar sections of a closed surface and girths as a tape takes them.

A tape measure laid round the body in a plane bridges every hollow between
the points it rests on, so a girth is the perimeter of the convex hull of the
planar section — of the section's loops that go round the part being measured
(e.g. the thigh, not the other thigh or a hand that the plane also cuts).
Those loops are the ones that enclose the part's centre, a point inside the
body on its axis. Everything is vectorised over the mesh: one signed distance
per vertex, one crossing point per crossed edge, loops as connected components.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse
from scipy.sparse import csgraph
from scipy.spatial import ConvexHull

from hitogata.geometry.topology import Topology
from hitogata.measure.geodesic import polyline_length


@dataclass(frozen=True)
class Section:
    """Crossing points of a plane with the surface, grouped into connected loops."""

    points: np.ndarray  # (M, 3) one point per crossed edge
    edges: np.ndarray  # (M,) the crossed edge of each point (index into Topology.edges)
    loop: np.ndarray  # (M,) loop id of each point
    segments: np.ndarray  # (S, 2) point pairs joined inside one crossed face
    n_loops: int


@dataclass(frozen=True)
class Tape:
    """A girth: its length (m) and the hull polygon the tape follows (H, 3), in order."""

    girth: float
    path: np.ndarray


def plane_basis(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unit normal n and two unit vectors u, v spanning the plane (u, v, n right-handed)."""
    n = np.asarray(normal, dtype=np.float64)
    n = n / np.linalg.norm(n)
    helper = np.eye(3)[np.argmin(np.abs(n))]
    u = np.cross(helper, n)
    u /= np.linalg.norm(u)
    return n, u, np.cross(n, u)


def section(vertices: np.ndarray, topo: Topology, origin: np.ndarray, normal: np.ndarray) -> Section:
    """The plane through `origin` with `normal` cut with the surface.

    A vertex on the plane counts as lying on its positive side, so every
    crossed triangle has exactly two crossed edges and the loops are closed.
    """
    distance = (vertices - origin) @ (np.asarray(normal, dtype=np.float64) / np.linalg.norm(normal))
    positive = distance >= 0.0
    a, b = topo.edges[:, 0], topo.edges[:, 1]
    crossed = np.flatnonzero(positive[a] != positive[b])
    da, db = distance[a[crossed]], distance[b[crossed]]
    t = da / (da - db)
    points = vertices[a[crossed]] + t[:, None] * (vertices[b[crossed]] - vertices[a[crossed]])

    node = np.full(len(topo.edges), -1, dtype=np.int64)
    node[crossed] = np.arange(len(crossed))
    face_nodes = node[topo.face_edges]
    cut = np.maximum(np.maximum(face_nodes[:, 0], face_nodes[:, 1]), face_nodes[:, 2]) >= 0  # 15x .max(axis=1)
    pairs = np.sort(face_nodes[cut], axis=1)[:, 1:]  # the two crossed edges of each cut face
    graph = sparse.coo_matrix(
        (np.ones(len(pairs), dtype=np.int8), (pairs[:, 0], pairs[:, 1])), shape=(len(crossed),) * 2
    )
    n_loops, loop = csgraph.connected_components(graph, directed=False)
    return Section(points=points, edges=crossed, loop=loop, segments=pairs, n_loops=int(n_loops))


def loops_around(sec: Section, centre: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Ids of the loops that enclose `centre` (a point in the plane), by ray-crossing parity."""
    _, u, v = plane_basis(normal)
    rel = sec.points - centre
    x, y = rel @ u, rel @ v
    p, q = sec.segments[:, 0], sec.segments[:, 1]
    straddles = (y[p] > 0.0) != (y[q] > 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        x_at = x[p] + (x[q] - x[p]) * (0.0 - y[p]) / (y[q] - y[p])
    hits = straddles & (x_at > 0.0)
    counts = np.bincount(sec.loop[p[hits]], minlength=sec.n_loops)
    return np.flatnonzero(counts % 2 == 1)


def hull_perimeter(points: np.ndarray, normal: np.ndarray) -> Tape:
    """Perimeter of the convex hull of points lying in a plane, and the hull polygon."""
    n, u, v = plane_basis(normal)
    flat = np.stack([points @ u, points @ v], axis=1)
    hull = ConvexHull(flat)
    ring = points[hull.vertices]
    closed = flat[np.append(hull.vertices, hull.vertices[0])]
    return Tape(girth=polyline_length(closed), path=ring)


def tape_girth(
    vertices: np.ndarray,
    topo: Topology,
    origin: np.ndarray,
    normal: np.ndarray,
    centre: np.ndarray,
    part: np.ndarray | None = None,
    above: tuple[np.ndarray, np.ndarray, float] | None = None,
) -> Tape:
    """The girth a tape takes in the plane (origin, normal) round the loops enclosing `centre`.

    `centre` is projected onto the plane first. `part` (V,) bool, if given, marks
    the skin the tape may rest on: a section point counts only if its edge has an
    end there — so in a posture where the part's loop merges with its neighbour's
    (a thigh raised against the belly) the tape still goes round the part alone.
    `above` = (point, unit direction, offset), if given, keeps only the section points
    at least `offset` (m) along the direction from the point: a tape bridging below a line
    (the armscye's under the arm).
    Returns a NaN girth and an empty path when nothing of the part is cut there.
    """
    n = np.asarray(normal, dtype=np.float64) / np.linalg.norm(normal)
    centre = centre - ((centre - origin) @ n) * n
    sec = section(vertices, topo, origin, n)
    kept = np.isin(sec.loop, loops_around(sec, centre, n))
    if part is not None:
        ends = topo.edges[sec.edges]
        kept &= part[ends[:, 0]] | part[ends[:, 1]]
    points = sec.points
    if above is not None:
        points, kept = _cut(sec, kept, *above)
    if np.count_nonzero(kept) < 3:
        return Tape(girth=float("nan"), path=np.empty((0, 3)))
    return hull_perimeter(points[kept], n)


def _cut(sec: Section, kept: np.ndarray, point: np.ndarray, direction: np.ndarray,
         offset: float) -> tuple[np.ndarray, np.ndarray]:
    """The section's points with those where its kept segments cross the line `offset` along
    `direction` from `point` added (so the cut does not depend on the mesh), and the kept mask
    of the points at or beyond that line."""
    height = (sec.points - point) @ direction - offset
    p, q = sec.segments[:, 0], sec.segments[:, 1]
    crossing = kept[p] & kept[q] & ((height[p] >= 0.0) != (height[q] >= 0.0))
    p, q = p[crossing], q[crossing]
    t = height[p] / (height[p] - height[q])
    ends = sec.points[p] + t[:, None] * (sec.points[q] - sec.points[p])
    return np.vstack([sec.points, ends]), np.concatenate([kept & (height >= 0.0), np.ones(len(ends), dtype=bool)])


def arc_tape(vertices: np.ndarray, topo: Topology, ends: tuple[np.ndarray, np.ndarray, np.ndarray],
             centre: np.ndarray, normal: np.ndarray | None = None, part: np.ndarray | None = None,
             bounded: bool = True) -> Tape:
    """A tape laid from the first of `ends` over the second to the third (points of the
    surface) in their plane, or in the plane through the second with `normal` (the others
    projected onto it): the points of the section's loops round `centre` (and on the skin
    `part`, as in `tape_girth`) on the middle's side of the chord (and, if `bounded`, between
    the two ends along it), bridged where hollow as a tape bridges them. Its length is the
    hull's perimeter less the chord; its path runs from end to end (open)."""
    left, middle, right = ends
    if normal is None:
        normal = np.cross(middle - left, right - left)
    normal = normal / np.linalg.norm(normal)
    left, right = left - ((left - middle) @ normal) * normal, right - ((right - middle) @ normal) * normal
    sec = section(vertices, topo, middle, normal)
    chord = right - left
    along, across = chord / np.linalg.norm(chord), middle - left
    across = across - (across @ along) * along
    rel = sec.points - left
    between = (rel @ across > 0.0) & np.isin(sec.loop, loops_around(sec, centre - ((centre - middle) @ normal) * normal,
                                                                     normal))
    if part is not None:
        edge_ends = topo.edges[sec.edges]
        between &= part[edge_ends[:, 0]] | part[edge_ends[:, 1]]
    if bounded:
        between &= (rel @ along > 0.0) & (rel @ along < np.linalg.norm(chord))
    points = np.vstack([sec.points[between], left, right])
    n, u, v = plane_basis(normal)
    hull = ConvexHull(np.stack([points @ u, points @ v], axis=1)).vertices.tolist()
    i, j = hull.index(len(points) - 2), hull.index(len(points) - 1)
    if (i + 1) % len(hull) == j:  # the hull runs left → right along the chord: take the other way
        i, j = j, i
    ring = [hull[(i + k) % len(hull)] for k in range((j - i) % len(hull) + 1)]
    path = points[ring]
    return Tape(girth=polyline_length(path), path=path)


def split_tape(tape: Tape, point: np.ndarray) -> tuple[Tape, Tape]:
    """An open tape cut in two where it passes nearest `point` (the nearest point of its polyline, so the cut moves
    continuously with the point): the part from its first end to there and the part from there to its last end;
    their lengths sum to the tape's."""
    a, b = tape.path[:-1], tape.path[1:]
    step = b - a
    t = np.clip(np.einsum("ij,ij->i", point - a, step) / np.maximum(np.einsum("ij,ij->i", step, step), 1e-300),
                0.0, 1.0)
    nearest = a + t[:, None] * step
    k = int(np.argmin(np.linalg.norm(nearest - point, axis=1)))
    first, second = np.vstack([tape.path[:k + 1], nearest[k]]), np.vstack([nearest[k], tape.path[k + 1:]])
    return Tape(girth=polyline_length(first), path=first), Tape(girth=polyline_length(second), path=second)
