"""The body's elastic model: the volume model's labelled tets + the FEM core, ready for dynamics.

`build_elastic_model(body)` meshes the trunk (or the whole body), lifts the
mesh to quadratic tets, gives each tissue region its material, assembles K
and M, attaches the bone nodes to the skeleton, solves the lowest modes and
maps the FE nodes to the body's skin vertices. Everything is SI; the element
size alone is in millimetres, like the volume model's.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType

import numpy as np
import scipy.sparse as sp

from hitogata.elastic.mapping import DEFAULT_FADE, skin_reach, skin_vertex_map
from hitogata.elastic.materials import Materials, load_materials
from hitogata.errors import HitogataError
from hitogata.fem import (
    Modes,
    eigenstrain_load,
    gravity_load,
    mass_matrix,
    muscle_eigenstrain,
    no_modes,
    p2_mesh,
    rayleigh_coefficients,
    region_materials,
    solve_modes,
    sparsity,
    stiffness_matrix,
)
from hitogata.fem.assembly import DILATATIONS
from hitogata.fem.damping import check_rayleigh, damping_ratios as modal_damping_ratios
from hitogata.fem.elements import MATERIAL_SAMPLES, P2_EDGES, tet_geometry
from hitogata.options import BONE_MODES, BoneMode, CUT_MODES, CutMode, Dilatation, EigenSolver, Element, ELEMENTS, Extent
from hitogata.volume import VolumeModel, build_volume_model
from hitogata.volume.integrity import MIN_HOLD_WIDTH, face_pieces, hold_width
from hitogata.volume.trunk import segment_distance

if TYPE_CHECKING:
    from hitogata.body.model import Body

# Default lattice spacing (mm) per element type. P2 at 40 mm: the largest trunk model whose 40
# modes solve within the 10 s budget; with the soft tissue meshed round the bone capsules its 40
# frequencies are 1.4 % (mean; f1 5.8 %) from P2 at 20 mm (docs/elastic.md). P1 at 20 mm has
# about the same number of dof.
DEFAULT_ELEMENT_SIZES = {"P2": 40.0, "P1": 20.0}
# Rayleigh damping: ratio 0.2 at 2 Hz and at 10 Hz (≥ 0.15 in between), within the 0.1-0.5 of
# soft-tissue and whole-body resonances (docs/elastic.md).
DEFAULT_DAMPING = ((2.0, 0.2), (10.0, 0.2))
# ARPACK residual tolerance: eigenvalue errors ~tol², far below the 1 % discretisation target.
EIGEN_TOLERANCE = 1e-6
# Elastic bone: the nodes within this fraction of an element of each bone's axis (beyond the
# nearest) follow the skeleton, the rest of the bone deforms.
AXIS_BAND = 0.25


@dataclass(frozen=True, eq=False)
class ElasticSystem:
    """The assembled FE system of a volume model: mesh, skeleton attachment, materials, K and M."""

    element: Element
    points: np.ndarray  # (N, 3) rest node positions; P2: the P1 nodes first, then edge midpoints
    elements: np.ndarray  # (T, 10) or (T, 4)
    fixed_nodes: np.ndarray  # (B,) nodes that follow the skeleton
    fixed_bone: np.ndarray  # (B,) index into volume.bone_names of the bone each follows
    materials: Materials
    bone: BoneMode
    cuts: CutMode  # the trunk's cut faces
    dilatation: Dilatation  #: how K integrates the volumetric term (`fem.stiffness_matrix`)
    E: np.ndarray  # (T,) Pa, each element's mean (K and M sample the tissue inside the elements)
    nu: np.ndarray  # (T,) element mean
    rho: np.ndarray  # (T,) kg/m^3, element mean
    K: sp.csr_matrix  # (3N, 3N), node-major dofs
    M: sp.csr_matrix  # consistent mass, on K's sparsity pattern


@dataclass(frozen=True, eq=False)
class ElasticModel(ElasticSystem):
    """The elastic body: the assembled system plus its modes, damping and the map to the skin."""

    volume: VolumeModel
    modes: Modes  # lowest modes, mass-normalised, zero at the fixed nodes' dofs
    alpha: float  # 1/s
    beta: float  # s
    skin_vertex_map: sp.csr_matrix  # (V, N): skin vertex displacements = map @ (N, 3) nodal ones
    timings: Mapping[str, float]  # seconds per stage: mesh, assembly, modes, skin_map

    @property
    def region(self) -> np.ndarray:
        """(T,) tissue region index per element, into `region_names`."""
        return self.volume.region

    @property
    def region_names(self) -> tuple[str, ...]:
        """The tissue regions' names, by the index `region` holds ("bone", "viscera", "muscle", "skin")."""
        return self.volume.region_names

    @property
    def muscle_names(self) -> tuple[str, ...]:
        """The named muscle regions of the volume model, by index."""
        return self.volume.muscle_names

    @property
    def frequencies(self) -> np.ndarray:
        """Natural frequencies (Hz) of the modes, ascending."""
        return self.modes.frequencies

    @property
    def damping_ratios(self) -> np.ndarray:
        """Damping ratio of each mode under the Rayleigh damping (1 = critical)."""
        return modal_damping_ratios(self.modes.eigenvalues, self.alpha, self.beta)

    @property
    def region_volumes(self) -> dict[str, float]:
        """Volume (m^3) of each tissue region ("bone": also the capsules held outside the mesh)."""
        return dict(self.volume.quality.region_volumes)

    @property
    def mass(self) -> float:
        """Mass (kg) of the elements: the soft tissue, and the bone where it is meshed (elastic bone)."""
        return float(self.rho @ tet_geometry(self.points, self.elements)[1])

    def muscle_elements(self, name: str) -> np.ndarray:
        """Indices of the elements holding some of a named muscle (at their sample points)."""
        return np.flatnonzero((self.volume.muscle_samples == self._muscle_index(name)).any(axis=1))

    def muscle_load(self, name: str, contraction: float) -> np.ndarray:
        """Nodal forces (3N,) of a muscle contracting by `contraction` along its fibres.

        An isochoric eigenstrain (fibre strain -contraction, the cross-section
        thickening at constant volume) where the muscle is: at the sample
        points of its elements that lie in it, with the tissue's own E and
        nu there (as K has them); positive contraction shortens, negative
        stretches (the paper's experiment).
        """
        if not np.isfinite(contraction):
            raise HitogataError(f"contraction {contraction!r} of {name!r}: allowed a finite number (strain)")
        mine = self.muscle_elements(name)
        inside = self.volume.muscle_samples[mine] == self._muscle_index(name)  # (n, Q)
        fibres = np.where(inside[..., None], self.volume.fibre_samples[mine], [1.0, 0.0, 0.0])
        strain = muscle_eigenstrain(fibres.reshape(-1, 3), contraction).reshape(*inside.shape, 3, 3)
        E, nu, _ = region_materials(self.volume.region_samples, self.materials.table(self.region_names))
        return eigenstrain_load(self.points, self.elements, E, nu, strain * inside[..., None, None], elements=mine)

    def _muscle_index(self, name: str) -> int:
        if name not in self.muscle_names:
            raise HitogataError(f"muscle {name!r} has no region in the elastic body; allowed: "
                                f"{', '.join(self.muscle_names)}")
        return self.muscle_names.index(name)

    def gravity_load(self, g: tuple[float, float, float] = (0.0, -9.81, 0.0)) -> np.ndarray:
        """Nodal forces (3N,) of the body's weight under acceleration g (m/s^2; default down)."""
        return gravity_load(self.points, self.elements, self.rho, g)

    def skin_displacement(self, u: np.ndarray) -> np.ndarray:
        """Displacements (V, 3) of the body's skin vertices from nodal displacements (3N,) or (N, 3)."""
        return self.skin_vertex_map @ np.asarray(u, dtype=float).reshape(len(self.points), 3)


def build_elastic_model(body: Body, *, extent: Extent = "trunk", element_size: float | None = None, element: Element = "P2",
                        n_modes: int = 40, materials: str | Path | Materials | None = None, bone: BoneMode = "rigid",
                        cuts: CutMode = "free", dilatation: Dilatation = "mean",
                        damping_ratios: tuple[tuple[float, float], tuple[float, float]] | None = None,
                        alpha_beta: tuple[float, float] | None = None, solver: EigenSolver = "auto",
                        volume: VolumeModel | None = None) -> ElasticModel:
    """The elastic model of a `hitogata.body.Body`.

    extent: "trunk" (the paper's) or "body"; element_size: lattice spacing in
    mm (default per element type, `DEFAULT_ELEMENT_SIZES`); element: "P2"
    (quadratic tets, default) or "P1"; n_modes: the lowest modes to solve (0: none, for
    held postures, which need none); materials: a TOML path, a `Materials`,
    or None for the shipped defaults; bone: "rigid" (bone nodes follow the
    skeleton) or "elastic" (bone deforms, only its axis follows the
    skeleton); cuts: "free" (the paper's bare trunk: fixed_nodes are the bone
    nodes) or "attached" (the trunk's cut faces also follow their nearest
    bone, as the neck, arms and thighs would hold them in small vibrations);
    dilatation: "mean" (default: the volumetric term on each element's mean
    dilatation, free of the locking of nearly incompressible tissue) or
    "full" (the plain displacement element), see `fem.stiffness_matrix`;
    damping: `damping_ratios` ((f1 Hz, zeta1), (f2 Hz, zeta2)) or
    `alpha_beta` (alpha 1/s, beta s), default the materials file's [damping], else `DEFAULT_DAMPING`; solver: see
    `hitogata.fem.solve_modes`; volume: a volume model of this body already
    built (skips meshing; extent and element_size are then its own).
    """
    _check_options(element, bone, cuts, dilatation)
    table = materials if isinstance(materials, Materials) else load_materials(materials)
    if damping_ratios is None and alpha_beta is None:
        alpha_beta = table.rayleigh
    alpha, beta = _rayleigh(damping_ratios, alpha_beta)
    timings: dict[str, float] = {}

    start = time.perf_counter()
    if volume is None:
        size = DEFAULT_ELEMENT_SIZES[element] if element_size is None else element_size
        # Rigid bone: the soft tissue meshed round the bone capsules; elastic bone needs bone tets.
        volume = build_volume_model(body.vertices, body.faces, body.rig, body.skin_weights, bmi=body.bmi,
                                    sex=body.params.sex, extent=extent, element_size=size,
                                    bones="labelled" if bone == "elastic" else "conforming")
    timings["mesh"] = time.perf_counter() - start

    start = time.perf_counter()
    system = assemble_system(volume, body.rig, element=element, materials=table, bone=bone, cuts=cuts,
                             dilatation=dilatation)
    timings["assembly"] = time.perf_counter() - start

    start = time.perf_counter()
    modes = no_modes(len(system.points)) if n_modes == 0 else solve_modes(
        system.K, system.M, n_modes, system.fixed_nodes, solver=solver, tol=EIGEN_TOLERANCE)
    timings["modes"] = time.perf_counter() - start

    start = time.perf_counter()
    skin_map = skin_vertex_map(body.vertices, system.points, system.elements,
                               skin_reach(volume.quality.surface_distance_max, volume.element_size), DEFAULT_FADE)
    timings["skin_map"] = time.perf_counter() - start
    return ElasticModel(volume=volume, **vars(system), modes=modes, alpha=alpha, beta=beta,
                        skin_vertex_map=skin_map, timings=MappingProxyType(timings))


def assemble_system(volume: VolumeModel, rig, *, element: Element = "P2", materials: str | Path | Materials | None = None,
                    bone: BoneMode = "rigid", cuts: CutMode = "free", dilatation: Dilatation = "mean") -> ElasticSystem:
    """Lift the volume model's mesh to `element`, attach bone nodes to `rig`'s bones, assemble K and M.

    rig: the body's rig (bone names, heads, tails). cuts: "free" (default, the
    paper's bare trunk) leaves the trunk's cut faces (neck, hips, arms) free
    surfaces; "attached" holds them to their nearest bone, as the body beyond
    them would for small vibrations (see docs/elastic.md). The materials are
    taken at each element's sample points (`volume.region_samples`), so a
    tissue interface inside an element counts where it lies.
    """
    _check_options(element, bone, cuts, dilatation)
    table = materials if isinstance(materials, Materials) else load_materials(materials)
    fixed, fixed_bone = volume.bone_nodes, volume.bone_node_bone
    if bone == "elastic":
        if not np.any(volume.region == volume.region_names.index("bone")):
            raise HitogataError("bone 'elastic' needs bone elements: a volume model built with bones='labelled'")
        fixed, fixed_bone = _axis_nodes(volume, rig)
    if cuts == "attached":
        fixed, fixed_bone = _with_cut_nodes(volume, rig, fixed, fixed_bone)
    fixed, fixed_bone = _with_loose_pieces(volume, rig, fixed, fixed_bone)
    points, elements = volume.nodes, volume.tets
    if element == "P2":
        points, elements = p2_mesh(points, elements)
        fixed, fixed_bone = _lift(elements, fixed, fixed_bone, len(points))
    E, nu, rho = region_materials(volume.region_samples, table.table(volume.region_names))
    pattern = sparsity(elements, len(points))
    K = stiffness_matrix(points, elements, E, nu, pattern, dilatation=dilatation)
    M = mass_matrix(points, elements, rho, pattern=pattern)
    weights = MATERIAL_SAMPLES[1]
    return ElasticSystem(element=element, points=points, elements=elements, fixed_nodes=fixed, fixed_bone=fixed_bone,
                         materials=table, bone=bone, cuts=cuts, dilatation=dilatation, E=E @ weights,
                         nu=nu @ weights, rho=rho @ weights, K=K, M=M)


def _check_options(element: str, bone: str, cuts: str, dilatation: str) -> None:
    for name, value, allowed in (("element", element, ELEMENTS), ("bone", bone, BONE_MODES), ("cuts", cuts, CUT_MODES),
                                 ("dilatation", dilatation, DILATATIONS)):
        if value not in allowed:
            raise HitogataError(f"{name} {value!r}: allowed {', '.join(allowed)}")


def _rayleigh(ratios, alpha_beta) -> tuple[float, float]:
    """(alpha, beta) from target damping ratios or given directly (not both)."""
    if ratios is not None and alpha_beta is not None:
        raise HitogataError("damping: give damping_ratios or alpha_beta, not both")
    if alpha_beta is not None:
        alpha, beta = (float(v) for v in alpha_beta)
        check_rayleigh(alpha, beta)
        return alpha, beta
    (f1, z1), (f2, z2) = DEFAULT_DAMPING if ratios is None else ratios
    return rayleigh_coefficients(z1, f1, z2, f2)


def _lift(elements2: np.ndarray, nodes: np.ndarray, bones: np.ndarray, n_nodes: int) -> tuple[np.ndarray, np.ndarray]:
    """A P1 node set and its bones carried to the P2 mesh: a midpoint between two of the nodes
    joins the set and follows the bone of the edge's first end (as `fem.lift_node_set`)."""
    bone_of = np.full(n_nodes, -1, dtype=np.int64)
    bone_of[nodes] = bones
    first, second = elements2[:, P2_EDGES[:, 0]], elements2[:, P2_EDGES[:, 1]]
    both = (bone_of[first] >= 0) & (bone_of[second] >= 0)
    bone_of[elements2[:, 4:][both]] = bone_of[first[both]]
    lifted = np.flatnonzero(bone_of >= 0)
    return lifted, bone_of[lifted]


def bone_segments(volume: VolumeModel, rig) -> tuple[np.ndarray, np.ndarray]:
    """Heads and tails (B, 3) of the volume model's bones, in `volume.bone_names` order."""
    rows = [rig.names.index(name) for name in volume.bone_names]
    return np.asarray(rig.heads)[rows], np.asarray(rig.tails)[rows]


def _with_cut_nodes(volume: VolumeModel, rig, nodes: np.ndarray, bones: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A node set plus the nodes of the cut faces (not on the skin), each with its nearest bone."""
    cut = np.setdiff1d(np.unique(volume.cut_faces), nodes)
    if cut.size == 0:
        return nodes, bones
    nearest = segment_distance(volume.nodes[cut], *bone_segments(volume, rig)).argmin(axis=1)
    order = np.argsort(np.concatenate([nodes, cut]))
    return np.concatenate([nodes, cut])[order], np.concatenate([bones, nearest])[order]


def _with_loose_pieces(volume: VolumeModel, rig, nodes: np.ndarray, bones: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A node set plus every node of a mesh piece not held by it, each following its nearest bone.

    Pieces are the tets connected through shared faces: a lattice island or a few
    tets hanging on by an edge or a corner (a fingertip at a coarse size) would
    float free or hinge, i.e. have zero-frequency modes. A piece is held if its
    nodes in the set span a triangle at least `volume.integrity.MIN_HOLD_WIDTH`
    high (a piece touching a bone capsule at one node or along a line hinges
    about it). The whole body's mesh is repaired so that none is left
    (`hitogata.volume.repair`); the trunk's may keep a few.
    """
    tets = volume.tets
    piece = face_pieces(tets)
    is_fixed = np.zeros(len(volume.nodes), dtype=bool)
    is_fixed[nodes] = True
    corner_piece, corner_node = np.repeat(piece, 4), tets.ravel()
    touching = np.unique(np.stack([corner_piece, corner_node], axis=1)[is_fixed[corner_node]], axis=0)
    starts = np.flatnonzero(np.r_[True, np.diff(touching[:, 0]) > 0])
    held = np.zeros(piece.max() + 1, dtype=bool)
    for k, members in zip(touching[starts, 0], np.split(touching[:, 1], starts[1:])):
        held[k] = hold_width(volume.nodes[members]) >= MIN_HOLD_WIDTH
    loose = np.setdiff1d(np.unique(tets[~held[piece]]), nodes)
    if loose.size == 0:
        return nodes, bones
    nearest = segment_distance(volume.nodes[loose], *bone_segments(volume, rig)).argmin(axis=1)
    order = np.argsort(np.concatenate([nodes, loose]))
    return np.concatenate([nodes, loose])[order], np.concatenate([bones, nearest])[order]


def _axis_nodes(volume: VolumeModel, rig) -> tuple[np.ndarray, np.ndarray]:
    """The bone nodes nearest each bone's axis (within `AXIS_BAND` elements of the nearest)."""
    heads, tails = bone_segments(volume, rig)
    nodes, bones = volume.bone_nodes, volume.bone_node_bone
    d = segment_distance(volume.nodes[nodes], heads, tails)[np.arange(len(nodes)), bones]
    nearest = np.full(len(heads), np.inf)
    np.minimum.at(nearest, bones, d)
    keep = d <= nearest[bones] + AXIS_BAND * volume.element_size
    return nodes[keep], bones[keep]
