"""The skeleton in the volume: capsules round the rig bones, as a hole the soft tissue is meshed around.

Each bone is a capsule (the points within a radius of its head→tail segment).
The soft-tissue domain is the body outside the union of the capsules; the
mesher then puts nodes on the capsules' surface (the boundary part `PART`),
and those nodes are the ones held by the skeleton: the held boundary is the
capsule surface itself, not a staircase of lattice tets, so the modes are
smooth there and converge at the element's rate.
"""

from __future__ import annotations

import numpy as np

from hitogata.volume.domain import ImplicitDomain
from hitogata.volume.trunk import segment_distance

PART = "bone"  # the name of the capsules' surface among a domain's boundary parts


def capsule_gap(points: np.ndarray, heads: np.ndarray, tails: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """Distance (P, B) from each point to each capsule's surface, negative inside it."""
    return segment_distance(points, heads, tails) - radii


def outside_capsules(heads: np.ndarray, tails: np.ndarray, radii: np.ndarray) -> ImplicitDomain:
    """The points outside every capsule, as a domain whose boundary part is `PART`."""
    def function(points: np.ndarray) -> np.ndarray:
        return -capsule_gap(points, heads, tails, radii).min(axis=1)

    return ImplicitDomain(function, PART)


def attach_surface_nodes(nodes: np.ndarray, node_part: np.ndarray, part: int, heads: np.ndarray,
                         tails: np.ndarray, radii: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The nodes on the capsules' surface (boundary part index `part`) and the capsule (B,) each lies on."""
    held = np.flatnonzero(node_part == part)
    return held, capsule_gap(nodes[held], heads, tails, radii).argmin(axis=1)


def held_volume(domain, heads: np.ndarray, tails: np.ndarray, radii: np.ndarray, spacing: float) -> float:
    """Volume (m³) of the union of the capsules within `domain`, counted at the centres of grid cells.

    Each capsule's bounding box is counted on its own grid; a point inside several
    capsules counts for the first only.
    """
    total = 0.0
    for i in range(len(heads)):
        lo = np.minimum(heads[i], tails[i]) - radii[i]
        hi = np.maximum(heads[i], tails[i]) + radii[i]
        counts = np.maximum(np.ceil((hi - lo) / spacing).astype(int), 1)
        steps = (hi - lo) / counts
        axes = [a + d * (np.arange(n) + 0.5) for a, d, n in zip(lo, steps, counts)]
        grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
        gap = capsule_gap(grid, heads[: i + 1], tails[: i + 1], radii[: i + 1])
        mine = grid[(gap[:, i] < 0) & (gap[:, :i] >= 0).all(axis=1)]
        total += int(domain.contains(mine).sum()) * float(np.prod(steps))
    return total
