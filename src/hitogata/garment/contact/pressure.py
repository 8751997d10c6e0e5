"""The interface pressure from the contact forces: the force pressing each skin node in, per its skin area.

The barrier's force on a skin node is the garment's push there; over the
node's share of the skin's area (a third of each triangle it is a corner of)
it is a pressure (Pa). On a faceted skin the force concentrates where the
fabric bends over the skin's edges, so a node's own value swings by ±20 %
about the true pressure wherever the garment's and the skin's meshes do not
line up; a pressure means something over a patch of a few nodes — as a
pressure sensor reads it (`patch_pressure`: the forces summed over the
patch, over its area), or round a whole girth band for a level.
"""

from __future__ import annotations

import numpy as np

from hitogata.geometry.normals import vertex_areas, vertex_normals


def pressing_forces(points: np.ndarray, faces: np.ndarray, force: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each node's contact force along its inward normal (N,) (N; positive pressing in) and its share of
    the surface's area (N,) (m²): points (N, 3), outward faces, the contact force on each node (N, 3)."""
    return -np.einsum("ni,ni->n", force, vertex_normals(points, faces)), vertex_areas(points, faces)


def node_pressure(points: np.ndarray, faces: np.ndarray, force: np.ndarray) -> np.ndarray:
    """(N,) Pa at each node of the surface: its pressing force over its area; 0 off the surface."""
    pressing, areas = pressing_forces(points, faces, force)
    out = np.zeros(len(points))
    on = areas > 0
    out[on] = pressing[on] / areas[on]
    return out


def patch_pressure(pressing: np.ndarray, areas: np.ndarray, chosen: np.ndarray) -> float:
    """Mean pressure (Pa) over the chosen nodes' patch of skin: their forces over their area (NaN if none)."""
    area = float(areas[chosen].sum())
    return float(pressing[chosen].sum()) / area if area > 0 else float("nan")
