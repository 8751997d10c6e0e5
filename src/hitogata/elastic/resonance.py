"""How a body region's soft tissue rings after an impact on the skeleton: its frequency and damping.

Soft-tissue vibration studies tap the skin, or let the heel strike the ground,
and read the damped oscillation of the tissue over a muscle with an
accelerometer: its frequency and damping. The elastic whole body answers the
same: the skeleton moves as a rigid base (bone nodes are held by it), so a
base acceleration along d loads mode i by its participation Γᵢ = φᵢᵀ M r_d
(r_d: every node moved by a unit step along d). The region's response in
mode i carries the kinetic energy Eᵢ = Γᵢ² sᵢ (summed over the three
directions), with sᵢ = φᵢ,ᵣᵀ M φᵢ,ᵣ the mode's energy in the region's nodes.
The region's frequency is the energy-weighted mean of the modes'
frequencies, its damping ratio the energy-weighted mean of the modes'
Rayleigh ratios α / 2ω + β ω / 2: the centre of the response's spectrum, a
smooth function of the constants (a single mode's would jump from one mode
to the next as they change), over the modes solved (the lowest 60 hold the
response up to ~8 Hz on the default bodies).

Regions are the soft tissue round named bones of the rig, both sides; a
side of the bone (behind: the calf; in front: the shin, the abdomen, the
breast) narrows them where the studies put their sensors.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from hitogata.errors import HitogataError
from hitogata.fem.damping import damping_ratios
from hitogata.fem.modes import frequencies_hz
from hitogata.geometry.tets import signed_volumes
from hitogata.volume.trunk import segment_distance

if TYPE_CHECKING:
    from hitogata.body.rig import Rig
    from hitogata.volume.model import VolumeModel

# region → (rig bones without side, which side of the bone: +1 in front (+z), -1 behind, 0 all round)
REGIONS: dict[str, tuple[tuple[str, ...], int]] = {
    "thigh": (("upperleg01", "upperleg02"), 0),
    "calf": (("lowerleg01", "lowerleg02"), -1),
    "shin": (("lowerleg01", "lowerleg02"), +1),
    "upper_arm": (("upperarm01", "upperarm02"), 0),
    "forearm": (("lowerarm01", "lowerarm02"), 0),
    "abdomen": (("spine05", "spine04", "spine03", "pelvis"), +1),
    "breast": (("spine02", "spine01", "clavicle"), +1),
}


@dataclass(frozen=True)
class Resonance:
    """A region's response: its frequency (Hz) and damping ratio (energy-weighted over the modes), the mode
    holding most of its energy and that mode's share (0..1) of it."""

    region: str
    frequency: float
    damping_ratio: float
    dominant_mode: int
    dominant_share: float


def region_nodes(points: np.ndarray, bone_names: tuple[str, ...], heads: np.ndarray, tails: np.ndarray,
                 region: str) -> np.ndarray:
    """Indices of the nodes (points (N, 3), rest) whose nearest bone is one of the region's, on its side."""
    if region not in REGIONS:
        raise HitogataError(f"soft-tissue region {region!r}: allowed {', '.join(REGIONS)}")
    bones, side = REGIONS[region]
    mine = np.array([any(name.split(".")[0] == b or name.startswith(b + ".") for b in bones) for name in bone_names])
    if not mine.any():
        raise HitogataError(f"soft-tissue region {region!r}: the elastic model holds none of its bones "
                            f"({', '.join(bones)}); build the whole body (extent 'body')")
    distance = segment_distance(points, heads, tails)
    nearest = distance.argmin(axis=1)
    inside = mine[nearest]
    if side:
        d = tails[nearest] - heads[nearest]
        t = np.clip(np.einsum("nk,nk->n", points - heads[nearest], d) / np.einsum("nk,nk->n", d, d), 0.0, 1.0)
        offset = points - (heads[nearest] + t[:, None] * d)
        inside &= side * offset[:, 2] > 0.0
    return np.flatnonzero(inside)


# The share of a region's volume its tissue elements must fill for the region's resonance to be the model's
# answer (`region_coverage`). On the default female and male at the 40 mm lattice: the thigh 89 and 78 %, the
# calf 77 and 70 %, the upper arm 45 and 78 %, the forearm 2 and 23 %, the shin's thin tissue over the tibia 21
# and 19 %; the abdomen and breast over 100 % (their nodes reach the deep tissue in front of the spine, beyond
# the skin's hull). Below half, the lattice does not model the region's tissue, and its ringing is not the
# region's.
MIN_COVERAGE = 0.5


def region_coverage(points: np.ndarray, elements: np.ndarray, nodes: np.ndarray, skin: np.ndarray) -> float:
    """The share of a region's volume that the tissue mesh fills: the volume of the elements (corner nodes
    `elements` (E, 4) into `points`) with three or four corners in the region (`nodes`), over the convex hulls of
    the region's skin vertices (`skin` (S, 3), found by `region_nodes` on the skin), one hull each side of the
    body's midplane (x = 0)."""
    from scipy.spatial import ConvexHull, QhullError

    inside = np.isin(elements, nodes).sum(axis=1) >= 3
    filled = float(np.abs(signed_volumes(points, elements[inside])).sum())
    hull = 0.0
    for side in (skin[:, 0] < 0.0, skin[:, 0] >= 0.0):
        if side.sum() >= 4:
            try:
                hull += ConvexHull(skin[side]).volume
            except QhullError:  # flat: no volume
                pass
    return filled / hull if hull > 0.0 else 0.0


def body_region_coverage(volume: VolumeModel, rig: Rig, skin: np.ndarray, region: str) -> float:
    """`region_coverage` of a body's tissue mesh (its volume model's corner mesh) round the rig's bones of
    `region`, against the body's skin (V, 3) round the same bones."""
    from hitogata.elastic.model import bone_segments

    heads, tails = bone_segments(volume, rig)
    nodes = region_nodes(volume.nodes, volume.bone_names, heads, tails, region)
    own = region_nodes(skin, tuple(rig.names), np.asarray(rig.heads), np.asarray(rig.tails), region)
    return region_coverage(volume.nodes, volume.tets, nodes, skin[own])


def region_energy(M: sp.spmatrix, vectors: np.ndarray, nodes: np.ndarray) -> np.ndarray:
    """(k,) each mass-normalised mode's kinetic energy share in the given nodes (φᵣᵀ Mᵣᵣ φᵣ)."""
    dofs = (3 * nodes[:, None] + np.arange(3)).ravel()
    part = vectors[dofs]
    return np.einsum("ik,ik->k", part, sp.csr_matrix(M)[dofs][:, dofs] @ part)


def participation(M: sp.spmatrix, vectors: np.ndarray) -> np.ndarray:
    """(3, k) participation of each mode in a rigid base acceleration along x, y and z."""
    n = M.shape[0] // 3
    r = np.zeros((M.shape[0], 3))
    for axis in range(3):
        r[axis::3, axis] = 1.0
    return (vectors.T @ (M @ r)).T if n else np.zeros((3, vectors.shape[1]))


def response_energy(M: sp.spmatrix, vectors: np.ndarray, nodes: np.ndarray) -> np.ndarray:
    """(k,) each mode's share of the region's kinetic energy after a base impact (summing to 1)."""
    energy = (participation(M, vectors) ** 2).sum(axis=0) * region_energy(M, vectors, nodes)
    return energy / energy.sum()


def weighted_response(region: str, eigenvalues: np.ndarray, weights: np.ndarray, alpha: float, beta: float
                      ) -> Resonance:
    """The region's frequency and damping ratio from each mode's energy share (`response_energy`)."""
    k = int(np.argmax(weights))
    return Resonance(region, float(weights @ frequencies_hz(eigenvalues)),
                     float(weights @ damping_ratios(eigenvalues, alpha, beta)), k, float(weights[k]))


def resonance(M: sp.spmatrix, eigenvalues: np.ndarray, vectors: np.ndarray, nodes: np.ndarray, alpha: float,
              beta: float, region: str) -> Resonance:
    """The region's response to a base impact: frequency and damping ratio (see the module's text)."""
    if len(nodes) == 0:
        raise HitogataError(f"soft-tissue region {region!r}: no node of the elastic model lies in it")
    return weighted_response(region, eigenvalues, response_energy(M, vectors, nodes), alpha, beta)
