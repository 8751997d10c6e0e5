"""The tissue regions' boundaries as smooth closed surfaces, from the regions' own definitions.

The regions are defined by where a point lies, not by the mesh
(`volume.regions`): its depth under the skin, the bone capsules, the trunk's
landmarks. So their boundaries are drawn from those definitions, on a grid far
finer than any elastic mesh, over the whole body (hands, feet and head
included, which no lattice of 40 mm holds):

- each region's own margin field (m, > 0 inside): the least of the margins of
  the conditions that define it and the greatest margin of those that exclude
  it, with the signed depth under the skin (> 0 inside the body). The bones
  come first, as the conforming mesh has them (its holes: `volume.bones`),
  then the skin+fat layer, the viscera and the muscle, as `tissue_regions`
  labels them;
- each region's surface: marching cubes on its field (libigl) at a level of
  `INSET`, so the surface lies that far inside its region: two regions that
  meet are drawn as two surfaces `2 INSET` apart rather than one surface twice
  (coincident translucent surfaces flicker). The fields vary linearly across a
  grid cell away from the regions' edges, so the surfaces have no staircase.

Built once per body (`body_region_surfaces`), with fewer triangles where they are drawn.
"""

from __future__ import annotations

from dataclasses import dataclass

import igl
import numpy as np
import scipy.sparse as sp
from scipy.ndimage import binary_dilation

from hitogata.volume import anatomy as A
from hitogata.volume.regions import bone_margin, viscera_margin
from hitogata.volume.surface import SurfaceIndex
from hitogata.volume.trunk import RigLike, TrunkLandmarks, arm_separator

GRID_SPACING = 0.008  # m: 2.5 grid cells across the thinnest layer drawn (the 20 mm muscle wall)
INSET = 0.001  # m: each surface this far inside its region (module note)
# Fewer triangles where they are drawn (libigl's quadric edge collapse, `simplified`): a picture of 360 x 540
# pixels a view shows no difference at 3 times fewer; a motion's GLB (a morph target per vertex and frame)
# stays within twice its size with the tissue of the 40 mm lattice at 3 times fewer again.
PICTURE_REDUCTION = 3
LIGHT_REDUCTION = 3
BONE_REACH = 4  # grid cells: the bone capsules are measured this far from their surface


@dataclass(frozen=True, eq=False)
class RegionSurface:
    """One tissue region's boundary at rest: vertices (V, 3) m and outward triangles (F, 3)."""

    name: str
    vertices: np.ndarray
    faces: np.ndarray


def region_fields(points: np.ndarray, signed_depth: np.ndarray, marks: TrunkLandmarks, trunk_side: np.ndarray,
                  bone: np.ndarray, skin: float, wall: float) -> np.ndarray:
    """(P, R) m: each region's margin at each point (> 0 inside it; columns in `anatomy.REGIONS` order).

    signed_depth: distance to the skin, > 0 inside the body; trunk_side: > 0 on the trunk's side of the
    trunk/arm separator (`trunk.arm_separator`, negated); bone: the capsules' margin (`regions.bone_margin`),
    the bones held before the skin as the conforming mesh holds them; skin, wall: the layers' thicknesses.
    """
    s = signed_depth
    viscera = np.minimum(viscera_margin(points, s, marks, skin, wall), trunk_side)
    fields = np.empty((len(points), len(A.REGIONS)))
    fields[:, A.BONE] = np.minimum(bone, s)
    fields[:, A.VISCERA] = np.minimum(viscera, -bone)
    fields[:, A.MUSCLE] = np.minimum.reduce([s - skin, -bone, -viscera])
    fields[:, A.SKIN] = np.minimum.reduce([s, skin - s, -bone])
    return fields


def build_region_surfaces(vertices: np.ndarray, faces: np.ndarray, rig: RigLike, weights: sp.csr_matrix, *,
                          bmi: float, sex: float, spacing: float = GRID_SPACING) -> tuple[RegionSurface, ...]:
    """The whole body's tissue regions as closed surfaces (module note), in `anatomy.REGIONS` order,
    on a grid of `spacing` (m). vertices/faces: the closed, outward skin (m); rig, weights, bmi (kg/m²)
    and sex (0 female … 1 male) as for `volume.build_volume_model`."""
    vertices = np.asarray(vertices, dtype=np.float64)
    index = SurfaceIndex(vertices, faces)
    lo = vertices.min(axis=0) - 2.0 * spacing
    shape = tuple(int(n) for n in np.ceil((vertices.max(axis=0) + 2.0 * spacing - lo) / spacing).astype(int) + 1)
    axes = [lo[k] + spacing * np.arange(shape[k]) for k in range(3)]
    # x fastest, as libigl's marching cubes reads the grid
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3, order="F")
    columns = shape[0] * shape[1]
    inside = index.contains_on_lines(grid[:columns, :2], np.tile(np.arange(columns), shape[2]),
                                     grid[:, 2]).reshape(shape, order="F")
    # every grid cell with a corner inside the body: its other corners take exact values too
    near = binary_dilation(inside, np.ones((3, 3, 3), dtype=bool)).ravel(order="F")
    points = grid[near]
    depth = index.distance(points)
    signed = np.where(inside.ravel(order="F")[near], depth, -depth)
    names = A.BODY_BONES
    rows = [rig.names.index(n) for n in names]
    heads, tails = np.asarray(rig.heads, dtype=np.float64)[rows], np.asarray(rig.tails, dtype=np.float64)[rows]
    trunk_side = -arm_separator(rig, vertices, weights)(points)
    fields = np.full((len(grid), len(A.REGIONS)), -spacing)  # outside, away from the skin
    # a capsule further off than a few cells changes no surface: a field's level set is where the other
    # conditions are near zero, so a bone margin clipped there leaves every minimum's sign as it was
    bone = bone_margin(points, heads, tails, A.capsule_radii(names), reach=BONE_REACH * spacing)
    fields[near] = region_fields(points, signed, TrunkLandmarks.from_rig(rig), trunk_side, bone,
                                 A.skin_thickness(bmi, sex), A.WALL)
    surfaces = []
    for k, name in enumerate(A.REGIONS):
        found, triangles, _ = igl.marching_cubes(np.ascontiguousarray(fields[:, k]), grid, *shape, INSET)
        # libigl orients the triangles towards the field's larger values: turned to face out of the region
        surfaces.append(RegionSurface(name, found.reshape(-1, 3), triangles.reshape(-1, 3)[:, ::-1].astype(np.int64)))
    return tuple(surfaces)


def simplified(surface: RegionSurface, reduction: int) -> RegionSurface:
    """The surface with `reduction` times fewer triangles: libigl's quadric edge collapse, refusing a
    collapse that would make the surface cross itself (volumes kept within 1 % at 9 times fewer on the
    default bodies)."""
    if len(surface.faces) < 4 * reduction:
        return surface
    found = igl.qslim(np.asfortranarray(surface.vertices), np.asfortranarray(surface.faces, dtype=np.int32),
                      len(surface.faces) // reduction, True)
    return RegionSurface(surface.name, np.asarray(found[0]), np.asarray(found[1], dtype=np.int64))


def _surfaces_of_body(body) -> tuple[RegionSurface, ...]:
    fine = build_region_surfaces(body.vertices, body.faces, body.rig, body.skin_weights,
                                 bmi=body.bmi, sex=body.params.sex)
    return tuple(simplified(surface, PICTURE_REDUCTION) for surface in fine)


def _light_surfaces_of_body(body) -> tuple[RegionSurface, ...]:
    return tuple(simplified(surface, LIGHT_REDUCTION) for surface in body_region_surfaces(body))


def body_region_surfaces(body, light: bool = False) -> tuple[RegionSurface, ...]:
    """The tissue regions' surfaces of a `hitogata.body.Body` at rest, for pictures (`build_region_surfaces`
    at `GRID_SPACING`, `PICTURE_REDUCTION` times fewer triangles) or, `light`, for an animation file
    (`LIGHT_REDUCTION` times fewer again); built once per body and kept with it (`Body.prepared`)."""
    return body.prepared(_light_surfaces_of_body if light else _surfaces_of_body)
