"""A garment made elsewhere: its mesh in the rest (sewn, relaxed) shape, read from OBJ or PLY.

A garment that wraps a limb or the trunk is a tube: one connected, edge-manifold triangle mesh open at
both ends (two boundary loops, Euler characteristic 0), every triangle of non-zero area. Its axis runs
from one opening's centre to the other's; its relaxed circumference at a share t of the way along is
the perimeter of its section by the plane across the axis there (the openings' own loops at t = 0 and
1), and its relaxed length is the axis's. The dressing (`dressing`) lays the mesh's openings at the
garment's first and last stations and takes its relaxed circumference at each station by the share of
the way along the segment: the tube's rings are the mesh's sections, its wale's rest length the mesh's
(a mesh shorter than the body's segment is stretched along it too). The solve is the tubular
garment's, so a mesh garment wraps a limb or the trunk as a tube does; a mesh's shape round a section
(a panel's seam, an asymmetric cut) is taken by its perimeter alone.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hitogata.errors import HitogataError
from hitogata.geometry.normals import triangle_areas

SECTIONS = 401  # relaxed circumferences sampled at this many shares of the way along the axis (every 2 mm of a legging)
MESH_UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001}
THINNEST = 1e-6  # least height of a triangle over its longest edge: below it the triangle is degenerate


@dataclass(frozen=True, eq=False)
class GarmentMesh:
    """A tubular garment mesh in its rest shape: vertices (V, 3) m and faces (F, 3), its relaxed length
    (m) and relaxed circumference (m) at `SECTIONS` shares of the way along its axis."""

    path: Path
    vertices: np.ndarray
    faces: np.ndarray
    length: float
    shares: np.ndarray
    circumferences: np.ndarray

    def relaxed(self, share: np.ndarray) -> np.ndarray:
        """The relaxed circumference (m) at shares (0 … 1) of the way along the garment."""
        return np.interp(np.asarray(share, dtype=float), self.shares, self.circumferences)


def read_garment_mesh(path: Path, where: str, unit: float = 1.0) -> GarmentMesh:
    """The garment mesh of file `path` (OBJ or PLY, lengths in metres × `unit`), checked: `where` names the
    garment file's entry in a refusal's one line."""
    import trimesh

    allowed = "allowed a triangle mesh (OBJ or PLY) of a tube open at both ends round the limb or trunk"
    here = f"{where}: {path.name}"
    if path.suffix.lower() not in (".obj", ".ply"):
        raise HitogataError(f"{where}: {path.name!r} is not an OBJ or PLY file; {allowed}")
    if not path.is_file():
        raise HitogataError(f"{here} does not exist; {allowed}")
    try:
        mesh = trimesh.load(str(path), force="mesh", process=False)
    except Exception as err:  # noqa: BLE001 — any reader failure is the user's file: one line
        raise HitogataError(f"{here} could not be read as a mesh ({err}); {allowed}") from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise HitogataError(f"{here} holds no triangles; {allowed}")
    mesh.merge_vertices()
    vertices = np.asarray(mesh.vertices, dtype=float) * unit
    faces = np.asarray(mesh.faces, dtype=np.int64)
    if not np.all(np.isfinite(vertices)):
        raise HitogataError(f"{here} has a vertex that is not a finite number; {allowed}")
    _check_triangles(vertices, faces, here)
    loops = _boundary_loops(faces, here, allowed)
    centres = [vertices[loop].mean(axis=0) for loop in loops]
    axis = centres[1] - centres[0]
    length = float(np.linalg.norm(axis))
    if length <= 0:
        raise HitogataError(f"{here}: its two openings share a centre; {allowed}")
    axis /= length
    shares = np.linspace(0.0, 1.0, SECTIONS)
    circumferences = np.empty(SECTIONS)
    circumferences[0], circumferences[-1] = (_loop_length(vertices, loop) for loop in loops)
    tri = trimesh.Trimesh(vertices, faces, process=False)
    for k, share in enumerate(shares[1:-1], start=1):
        origin = centres[0] + share * length * axis
        segments = trimesh.intersections.mesh_plane(tri, axis, origin)
        if not _round_the_axis(segments, origin, axis):
            raise HitogataError(f"{here}: its section {100 * share:.0f} % of the way between its openings "
                                f"does not go round the axis between them; {allowed}")
        circumferences[k] = float(np.linalg.norm(segments[:, 1] - segments[:, 0], axis=1).sum())
    return GarmentMesh(path, vertices, faces, length, shares, circumferences)


def _check_triangles(vertices: np.ndarray, faces: np.ndarray, where: str) -> None:
    """Refused (one line) for a degenerate triangle: repeated corners or a height under `THINNEST` of its
    longest edge."""
    corners = vertices[faces]
    edges = np.linalg.norm(corners - np.roll(corners, -1, axis=1), axis=2)
    longest = edges.max(axis=1)
    area = triangle_areas(corners)
    thin = ~(2 * area > THINNEST * longest ** 2)
    if thin.any():
        f = int(np.flatnonzero(thin)[0])
        raise HitogataError(f"{where}: triangle {f} (vertices {faces[f].tolist()}) is degenerate (area "
                            f"{area[f]:.3g} m²); allowed triangles of non-zero area")


def _boundary_loops(faces: np.ndarray, where: str, allowed: str) -> list[np.ndarray]:
    """The mesh's two boundary loops (vertex indices in order), after checking it is one connected,
    edge-manifold tube."""
    import trimesh

    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    if counts.max() > 2:
        raise HitogataError(f"{where}: an edge shared by {int(counts.max())} triangles; {allowed}")
    components = trimesh.graph.connected_components(unique, nodes=np.unique(faces))
    if len(components) != 1:
        raise HitogataError(f"{where}: {len(components)} separate pieces; {allowed}")
    open_edges = unique[counts == 1]
    loops: list[np.ndarray] = []
    if len(open_edges):
        for part in trimesh.graph.connected_components(open_edges):
            loop = _ordered_loop(open_edges, set(int(v) for v in part))
            if len(loop) != len(part):
                raise HitogataError(f"{where}: an opening's edges meet at vertex {int(loop[-1])} more than twice; "
                                    f"{allowed}")
            loops.append(loop)
    euler = len(np.unique(faces)) - len(unique) + len(faces)
    if len(loops) != 2 or euler != 0:
        what = "closed (no opening)" if not loops else f"{len(loops)} openings, Euler characteristic {euler}"
        raise HitogataError(f"{where}: {what}; {allowed}")
    return loops


def _ordered_loop(edges: np.ndarray, part: set[int]) -> np.ndarray:
    """One boundary loop's vertices in order round it."""
    neighbours: dict[int, list[int]] = {}
    for a, b in edges:
        if int(a) in part:
            neighbours.setdefault(int(a), []).append(int(b))
            neighbours.setdefault(int(b), []).append(int(a))
    start = min(part)
    loop, previous = [start], -1
    while len(loop) <= len(part):
        step = next((n for n in neighbours[loop[-1]] if n != previous), start)
        if step == start:
            break
        previous = loop[-1]
        loop.append(step)
    return np.array(loop)


def _loop_length(vertices: np.ndarray, loop: np.ndarray) -> float:
    ring = vertices[loop]
    return float(np.linalg.norm(np.roll(ring, -1, axis=0) - ring, axis=1).sum())


def _round_the_axis(segments: np.ndarray, origin: np.ndarray, axis: np.ndarray) -> bool:
    """Whether a section's segments (S, 2, 3) go once round the axis through `origin` (a section seen
    from the axis as one closed curve, each direction once)."""
    if len(segments) < 3:
        return False
    u = np.cross(axis, [1.0, 0.0, 0.0] if abs(axis[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(axis, u)
    d = segments - origin
    angle = np.arctan2(d @ v, d @ u)
    # the section's segments come in no order nor direction: round the axis once, their turns' sizes add
    # up to a whole turn
    turn = np.abs(np.angle(np.exp(1j * (angle[:, 1] - angle[:, 0]))))
    return bool(abs(turn.sum() - 2 * np.pi) < 0.1)
