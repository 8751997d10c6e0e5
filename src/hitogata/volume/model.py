"""The volumetric body model: a labelled tetrahedral mesh of the trunk or the whole body.

`build_volume_model` works on plain arrays (skin surface, rig, skinning
weights); `build_trunk_model` and `build_body_model` take a `hitogata.body.Body`.
The element size is given in millimetres (the lattice spacing h: the long edge
of the BCC tets; their mean edge is ≈ 0.91 h) and used in metres inside.

By default the mesh is the soft tissue only: the bone capsules are holes
whose surface nodes follow the skeleton (`hitogata.volume.bones`), so the
held boundary is smooth and the same at every element size; their volume is
the "bone" region's. `bones="labelled"` meshes the bones too, as the lattice
tets whose centroid lies in a capsule (for elastic bone).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Mapping

import numpy as np
import scipy.sparse as sp

from hitogata.errors import HitogataError
from hitogata.fem.elements import MATERIAL_SAMPLES, sample_points
from hitogata.geometry.mesh_checks import enclosed_volume, is_closed
from hitogata.options import BONE_MESHES, Extent, EXTENTS
from hitogata.volume import anatomy as A
from hitogata.volume.bones import PART as BONE_PART, attach_surface_nodes, capsule_gap, held_volume, outside_capsules
from hitogata.volume.domain import Domain, Intersection, SurfaceDomain
from hitogata.volume.integrity import MeshIntegrity, mesh_integrity
from hitogata.volume.lattice import stuff
from hitogata.volume.quality import boundary_faces, dihedral_angles, interface_faces, signed_volumes, surface_distances
from hitogata.volume.regions import attach_bone_nodes, muscle_regions, tissue_regions
from hitogata.volume.repair import Repair, repair
from hitogata.volume.trunk import TrunkLandmarks, RigLike, arm_separator, body_domain, trunk_domain

DEFAULT_ELEMENT_SIZE = 20.0  # mm: ~40k tets in an adult trunk, ~2 elements across the skin+muscle wall
ELEMENT_SIZE_RANGE = (4.0, 100.0)  # mm: finer runs out of memory on the whole body, coarser loses the trunk
# Reference volume of a cut trunk: counted on a grid 4× finer than the elements, but no
# finer than 4 mm (there the count's own error is ~0.02% of a trunk).
_REFERENCE_REFINEMENT = 4
_REFERENCE_MIN_SPACING = 0.004


@dataclass(frozen=True)
class VolumeQuality:
    """Element quality and fidelity to the skin (lengths m, volumes m³, angles degrees)."""

    n_nodes: int
    n_tets: int
    min_dihedral: float
    max_dihedral: float
    inverted: int
    volume: float  # of the tets plus the bone capsules left out of the mesh (`held_volume`)
    reference_volume: float
    volume_error: float  # relative: volume / reference − 1
    surface_distance_mean: float  # the mesh's skin faces to the skin
    surface_distance_max: float  # sampled Hausdorff distance, both ways
    closed: bool  # the boundary is a closed 2-manifold
    held_volume: float  # the bone capsules left out of the mesh (conforming bones; counted in "bone"), else 0
    region_volumes: Mapping[str, float] = field(default_factory=dict)
    integrity: MeshIntegrity | None = None  # pieces, pinches, manifold boundary, hold (`volume.integrity`)
    repaired: Repair | None = None  # whole body: what `volume.repair` split and removed of the stuffed mesh

    def summary(self) -> str:
        regions = ", ".join(f"{k} {v * 1e3:.2f} L" for k, v in self.region_volumes.items())
        return (
            f"{self.n_tets} tets, {self.n_nodes} nodes; dihedral {self.min_dihedral:.1f}°–{self.max_dihedral:.1f}°, "
            f"{self.inverted} inverted; volume {self.volume * 1e3:.2f} L ({self.volume_error * 100:+.2f}% vs skin); "
            f"surface distance mean {self.surface_distance_mean * 1e3:.2f} mm, max {self.surface_distance_max * 1e3:.1f} mm; "
            f"boundary {'closed' if self.closed else 'not closed'}; {regions}"
            + (f"; {self.integrity.summary()}" if self.integrity else "")
            + (f"; repair: {self.repaired.split} nodes split, {self.repaired.pinched + self.repaired.unheld} tets "
               f"({self.repaired.removed_volume * 1e3:.2f} L) removed" if self.repaired else "")
        )


@dataclass(frozen=True, eq=False)
class VolumeModel:
    """A tetrahedral mesh (metres) with a tissue region and maybe a named muscle per tet."""

    nodes: np.ndarray  # (N, 3)
    tets: np.ndarray  # (T, 4) positively oriented
    region: np.ndarray  # (T,) index into region_names, at the centroid
    region_samples: np.ndarray  # (T, Q) index into region_names at the material sample points
    region_names: tuple[str, ...]
    muscle: np.ndarray  # (T,) index into muscle_names, -1 for none, at the centroid
    muscle_samples: np.ndarray  # (T, Q) index into muscle_names at the material sample points, -1 for none
    muscle_names: tuple[str, ...]
    fibres: np.ndarray  # (T, 3) unit fibre direction in named-muscle tets, zero elsewhere
    fibre_samples: np.ndarray  # (T, Q, 3) unit fibre direction at the sample points of named muscles, else zero
    bone_nodes: np.ndarray  # (B,) nodes attached to the skeleton
    bone_node_bone: np.ndarray  # (B,) index into bone_names of the bone each is attached to
    bone_names: tuple[str, ...]  # rig bone names
    boundary_faces: np.ndarray  # (F, 3) outward triangles
    boundary_tets: np.ndarray  # (F,) the tet each boundary face belongs to
    boundary_on_skin: np.ndarray  # (F,) True on the skin, False on a cut (neck, hips, arms) or a bone
    boundary_on_bone: np.ndarray  # (F,) True on a bone capsule's surface (conforming bones)
    boundary_on_cut: np.ndarray  # (F,) True with a node on a cut plane (a trunk's neck, hips, arms; none in a body)
    interfaces: Mapping[tuple[str, str], np.ndarray]  # region pair → faces between them
    element_size: float  # m
    skin_thickness: float  # m
    wall_thickness: float  # m
    quality: VolumeQuality

    @property
    def region_fractions(self) -> np.ndarray:
        """(T, R) volume fraction of each region in each tet (from the material sample points)."""
        return _fractions(self.region_samples, len(self.region_names))

    @property
    def cut_faces(self) -> np.ndarray:
        """(C, 3) boundary triangles touching a cut (a trunk's neck, hips, arms): not a face where a
        bone capsule comes to the skin, nor one a repair opened (the whole body has no cut)."""
        return self.boundary_faces[self.boundary_on_cut]

    @property
    def bone_surface(self) -> np.ndarray:
        """(S, 3) the held bone capsules' surface (conforming bones), triangles facing out of the bone."""
        return self.boundary_faces[self.boundary_on_bone][:, ::-1]


def _check_size(element_size: float) -> float:
    lo, hi = ELEMENT_SIZE_RANGE
    if not (isinstance(element_size, (int, float)) and lo <= element_size <= hi):
        raise HitogataError(f"element_size {element_size!r} mm: allowed {lo:g}–{hi:g} mm")
    return float(element_size) * 1e-3


def _reference_volume(domain: Domain, lo: np.ndarray, hi: np.ndarray, spacing: float) -> float:
    """Volume of a domain within the box [lo, hi], counted at the centres of a grid of cells.

    Each axis is split into whole cells, so cut planes placed on the box's faces
    fall on cell faces and add no error (the count is then O(spacing²) accurate).
    """
    counts = np.maximum(np.ceil((hi - lo) / spacing).astype(int), 1)
    steps = (hi - lo) / counts
    axes = [a + d * (np.arange(n) + 0.5) for a, d, n in zip(lo, steps, counts)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    inside = sum(int(domain.contains(chunk).sum()) for chunk in np.array_split(grid, max(1, len(grid) // 200_000)))
    return inside * float(np.prod(steps))


def build_volume_model(vertices: np.ndarray, faces: np.ndarray, rig: RigLike, weights: sp.csr_matrix, *,
                       bmi: float, sex: float, extent: Extent = "trunk",
                       element_size: float = DEFAULT_ELEMENT_SIZE, bones: str = "conforming") -> VolumeModel:
    """Mesh and label the trunk (default, as in the paper) or the whole body.

    vertices/faces: the closed, outward skin (m); rig: bone names, heads, tails
    (m); weights: (V, B) skinning weights; bmi (kg/m²) and sex (0 female … 1
    male) set the skin+fat thickness; element_size in mm; bones: one of
    `BONE_MESHES`.
    """
    h = _check_size(element_size)
    if extent not in EXTENTS:
        raise HitogataError(f"extent {extent!r}: allowed {', '.join(EXTENTS)}")
    if bones not in BONE_MESHES:
        raise HitogataError(f"bones {bones!r}: allowed {', '.join(BONE_MESHES)}")
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    marks = TrunkLandmarks.from_rig(rig)
    cuts: tuple[Domain, ...] = ()  # the trunk's neck and hip planes and arm separator; none on the body
    if extent == "trunk":
        trunk, bounds = trunk_domain(vertices, faces, rig, weights)
        skin, cuts = trunk.members[0], trunk.members[1:]
        domain: Domain = trunk
    else:
        skin, bounds = body_domain(vertices, faces)
        domain = skin
    if not isinstance(skin, SurfaceDomain):  # trunk_domain puts the skin first
        raise TypeError(f"trunk domain: first member is a {type(skin).__name__}, not the skin surface")
    skin_index = skin.index
    bone_names = A.TRUNK_BONES if extent == "trunk" else A.BODY_BONES
    rows = [rig.names.index(n) for n in bone_names]
    heads, tails = np.asarray(rig.heads)[rows], np.asarray(rig.tails)[rows]
    radii = A.capsule_radii(bone_names, None if bones == "conforming" else h)
    whole = domain  # the body, bones included
    bone_part = -2  # the index of the capsules' surface among the boundary parts (none: no node has it)
    if bones == "conforming":
        domain = Intersection(domain, outside_capsules(heads, tails, radii))
        bone_part = domain.parts.index(BONE_PART)
    mesh = stuff(domain, h, bounds)
    mended = None
    if extent == "body":  # the trunk keeps the paper's model as stuffed (docs/elastic.md)
        if bones == "conforming":
            anchored = np.flatnonzero(mesh.node_part == bone_part)
        else:  # the corners of the lattice tets labelled bone below (centroid in a capsule)
            inside = capsule_gap(mesh.nodes[mesh.tets].mean(axis=1), heads, tails, radii).min(axis=1) < 0
            anchored = np.unique(mesh.tets[inside])
        mesh, mended = repair(mesh, anchored)
    nodes, tets = mesh.nodes, mesh.tets

    centroids = nodes[tets].mean(axis=1)
    depth, closest = skin_index.closest(centroids)
    normal = (closest - centroids) / np.maximum(depth, 1e-12)[:, None]
    arm_side = arm_separator(rig, vertices, weights)  # < 0 on the trunk side
    level = marks.level(centroids[:, 1])
    arm_offset = arm_side(centroids)
    in_trunk = (arm_offset < 0) & (level <= 1.0)
    skin_t = A.skin_thickness(bmi, sex)
    labelled = len(radii) if bones == "labelled" else 0  # how many capsules label tets as bone
    region = tissue_regions(centroids, depth, marks, in_trunk, heads[:labelled], tails[:labelled], radii[:labelled],
                            skin_t, A.WALL)
    eligible = in_trunk & (level >= A.LEVEL_GLUTEAL_FOLD)
    muscle, fibres = muscle_regions(centroids, region, normal, marks, eligible)
    region_samples, muscle_samples, fibre_samples = _tissue_samples(
        nodes, tets, region, skin_index.distance(nodes), normal, marks, arm_side, arm_offset, skin_t)
    if bones == "conforming":
        bone_nodes, bone_of = attach_surface_nodes(nodes, mesh.node_part, bone_part, heads, tails, radii)
    else:
        bone_nodes, bone_of = attach_bone_nodes(nodes, tets, region, heads, tails)

    bfaces, btets = boundary_faces(tets)
    on_skin = np.all(mesh.node_part[bfaces] == 0, axis=1)
    on_bone = np.all(mesh.node_part[bfaces] == bone_part, axis=1)
    cut_parts = [k for k, name in enumerate(domain.parts) if k != 0 and name != BONE_PART]
    on_cut = np.isin(mesh.node_part, cut_parts)[bfaces].any(axis=1)
    interfaces = {(A.REGIONS[a], A.REGIONS[b]): f for (a, b), f in interface_faces(tets, region).items()}

    spacing = max(h / _REFERENCE_REFINEMENT, _REFERENCE_MIN_SPACING)
    if extent == "trunk":
        lo, hi = bounds[0].copy(), bounds[1].copy()
        lo[1], hi[1] = marks.hip_height, marks.neck_height  # the cut planes
        reference = _reference_volume(whole, lo, hi, spacing)
        others = np.ones(len(vertices), dtype=bool)
        for member in cuts:
            others &= member.contains(vertices)
        skin_points = vertices[others]
    else:
        reference = enclosed_volume(vertices, faces)
        skin_points = vertices
    held = held_volume(whole, heads, tails, radii, spacing) if bones == "conforming" else 0.0
    quality = _quality(nodes, tets, region_samples, bfaces[on_skin], skin_index, skin_points, reference, held, bfaces,
                       mesh_integrity(nodes, tets, bone_nodes), mended)
    return VolumeModel(
        nodes=nodes, tets=tets, region=region, region_samples=region_samples, region_names=A.REGIONS,
        muscle=muscle, muscle_samples=muscle_samples, muscle_names=A.MUSCLES,
        fibres=fibres, fibre_samples=fibre_samples, bone_nodes=bone_nodes, bone_node_bone=bone_of,
        bone_names=tuple(bone_names),
        boundary_faces=bfaces, boundary_tets=btets, boundary_on_skin=on_skin,
        boundary_on_bone=on_bone, boundary_on_cut=on_cut,
        interfaces=MappingProxyType(interfaces), element_size=h, skin_thickness=skin_t, wall_thickness=A.WALL,
        quality=quality,
    )


def _tissue_samples(nodes: np.ndarray, tets: np.ndarray, region: np.ndarray, node_depth: np.ndarray,
                    normal: np.ndarray, marks: TrunkLandmarks, arm_side, arm_offset: np.ndarray,
                    skin_t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Tissue region (T, Q), named muscle (T, Q) and fibre (T, Q, 3) at each tet's material sample
    points (`fem.elements.MATERIAL_SAMPLES`).

    The layers cross the elements (a 40 mm tet straddles the ~20 mm skin and
    muscle layers), so the tissue is sampled inside each tet rather than
    taken from its centroid; depth below the skin is interpolated from the
    corners, the direction to the skin (for the fibres) is the tet's.
    Labelled bone tets stay bone throughout. `arm_side` is the trunk/arm
    separator and `arm_offset` its value at the centroids: it changes by at
    most twice the distance moved (a difference of two distances), so only
    tets within that of the separator are sampled anew.
    """
    points = sample_points(nodes, tets)
    shape = points.shape[:2]
    depth = (node_depth[tets] @ MATERIAL_SAMPLES[0].T).ravel()
    corners = nodes[tets]
    reach = np.linalg.norm(corners - corners.mean(axis=1, keepdims=True), axis=2).max(axis=1)
    offset = np.repeat(arm_offset[:, None], shape[1], axis=1)
    near = np.abs(arm_offset) <= 2.0 * reach
    offset[near] = arm_side(points[near].reshape(-1, 3)).reshape(-1, shape[1])
    points = points.reshape(-1, 3)
    level = marks.level(points[:, 1])
    in_trunk = (offset.ravel() < 0) & (level <= 1.0)
    none = np.zeros((0, 3))
    samples = tissue_regions(points, depth, marks, in_trunk, none, none, np.zeros(0), skin_t, A.WALL).reshape(shape)
    samples[region == A.BONE] = A.BONE
    eligible = in_trunk & (level >= A.LEVEL_GLUTEAL_FOLD)
    muscle, fibres = muscle_regions(points, samples.ravel(), np.repeat(normal, shape[1], axis=0), marks, eligible)
    return samples, muscle.reshape(shape), fibres.reshape(*shape, 3)


def _fractions(samples: np.ndarray, n_regions: int) -> np.ndarray:
    """(T, R) share of each region in each tet, from its labels (T, Q) at the material sample points."""
    weights = MATERIAL_SAMPLES[1]
    return np.stack([(samples == k) @ weights for k in range(n_regions)], axis=1)


def _quality(nodes, tets, region_samples, skin_faces, skin_index, skin_points, reference, held,
             all_faces, integrity, mended) -> VolumeQuality:
    angles = np.degrees(dihedral_angles(nodes, tets))
    volumes = signed_volumes(nodes, tets)
    # Skin → mesh uses the whole boundary, so skin next to a cut is not penalised for
    # the cut faces that end the skin faces there.
    forward, backward = surface_distances(nodes, skin_faces, skin_index, skin_points, all_faces)
    total = float(volumes.sum()) + held
    fractions = _fractions(region_samples, len(A.REGIONS))
    region_volumes = {name: float(volumes @ fractions[:, k]) for k, name in enumerate(A.REGIONS)}
    region_volumes["bone"] += held
    return VolumeQuality(
        n_nodes=len(nodes), n_tets=len(tets),
        min_dihedral=float(angles.min()), max_dihedral=float(angles.max()),
        inverted=int((volumes <= 0).sum()),
        volume=total, reference_volume=float(reference), volume_error=total / reference - 1.0,
        surface_distance_mean=float(forward.mean()),
        surface_distance_max=float(max(forward.max(), backward.max(initial=0.0))),
        closed=is_closed(all_faces), held_volume=float(held),
        region_volumes=MappingProxyType(region_volumes),
        integrity=integrity, repaired=mended,
    )


def build_trunk_model(body, element_size: float = DEFAULT_ELEMENT_SIZE) -> VolumeModel:
    """The trunk of a `hitogata.body.Body`, meshed and labelled (element_size in mm)."""
    return build_volume_model(body.vertices, body.faces, body.rig, body.skin_weights,
                              bmi=body.bmi, sex=body.params.sex, extent="trunk", element_size=element_size)


def build_body_model(body, element_size: float = DEFAULT_ELEMENT_SIZE) -> VolumeModel:
    """The whole body of a `hitogata.body.Body`, meshed and labelled (element_size in mm)."""
    return build_volume_model(body.vertices, body.faces, body.rig, body.skin_weights,
                              bmi=body.bmi, sex=body.params.sex, extent="body", element_size=element_size)
