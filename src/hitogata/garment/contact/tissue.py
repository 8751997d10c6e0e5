"""The soft tissue under a limb garment: a tet mesh of the limb between its bone and its skin.

The whole-body elastic model's 40 mm lattice leaves the lower leg's tissue one or two elements thick,
too coarse to resolve an indentation of millimetres (decision 0020), so the dressing meshes the limb
under the garment itself: at every `ALONG`-th station of the garment, a section of `LAYERS` radial
layers between the bone (a circle of the rig bone's capsule radius, `volume.anatomy.bone_radius`, round
where the bone's axis crosses the station's plane) and the skin's section (its convex hull, as the tape
and the garment take it), at every `AROUND`-th of the garment's angles, joined between stations into
P1 tets (`annulus_tets`, the same grid as the soft cylinder of `verify`, whose indentation matches
Lamé's). The outer `SKIN_LAYERS` are the skin region (dermis and subcutaneous fat, as thick as the
volume model's skin layer for the body's BMI and sex, `volume.anatomy.skin_thickness`), the rest
muscle; their moduli are the materials file's (`elastic.materials`). The bone nodes are held; the end
sections are held along the limb (the tissue beyond them), free across it.

Its stiffness K joins the garment's barrier problem (`equilibrium.settle`): garment and tissue are
solved together in one Newton, to its tolerance (a step's largest move under 10 µm, a Newton decrement
under 1e-5 of the energy, or a full step that changed no level's pressure or indentation by what is
printed of it: `readings`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from hitogata.body.model import Body
from hitogata.elastic.materials import Materials, load_materials
from hitogata.errors import HitogataError
from hitogata.fem.assembly import stiffness_matrix
from hitogata.fem.verify.box_mesh import box_mesh
from hitogata.garment.contact.equilibrium import ContactBody
from hitogata.garment.contact.tube import Stations
from hitogata.geometry.mesh_checks import enclosed_volume
from hitogata.geometry.tets import boundary_faces
from hitogata.volume.anatomy import bone_radius, skin_thickness

ALONG = 2  # a tissue section at every second garment station (2 cm apart)
AROUND = 2  # tissue nodes at every second of the garment's angles round a section
MUSCLE_LAYERS = 3  # radial element layers of muscle between the bone and the skin layer
SKIN_LAYERS = 2  # radial element layers of the skin region (dermis and subcutaneous fat)
LEAST_TISSUE = 0.003  # m: the least tissue between bone and skin a section may have
LIMB_BONES = {"leg": ("upperleg", "lowerleg"), "arm": ("upperarm", "lowerarm")}


def annulus_tets(radial: int, around: int, along: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """P1 tets of a grid closed round its middle index: node (i, j, k), i < radial + 1 from the inside
    out, j < around round, k < along + 1 along, at index (i · around + j) · (along + 1) + k. Returns the
    tets and each node's i, j, k."""
    points, tets = box_mesh((1.0, 1.0, 1.0), (radial, around, along))
    grid = (radial + 1, around + 1, along + 1)
    i, j, k = np.unravel_index(np.arange(len(points)), grid)
    keep = j < around  # the cell's last row round is its first: node (i, around, k) is node (i, 0, k)
    index = np.ravel_multi_index((i, j % around, k), grid)
    renumber = np.full(len(points), -1)
    renumber[np.flatnonzero(keep)] = np.arange(int(keep.sum()))
    return renumber[index[tets]], i[keep], j[keep], k[keep]


@dataclass(frozen=True, eq=False)
class LimbTissue:
    """The limb's tissue under the garment: the body to press on (nodes, outer faces, K, held dofs), its
    tets, the garment stations its sections lie on (m,), the outer nodes (m, n) section by section, their
    outward directions (m, n, 3)."""

    body: ContactBody
    tets: np.ndarray
    stations: np.ndarray
    outer: np.ndarray
    outward: np.ndarray
    section: np.ndarray  # (T,) each node's section (an index into `stations`)

    @property
    def perimeter(self) -> np.ndarray:
        """(m,) m: each section's outer polygon perimeter at rest."""
        return self.perimeters(self.body.points)

    def indentation(self, nodes: np.ndarray) -> np.ndarray:
        """(m, n) m: how far each outer node has moved in (along its outward direction; < 0 bulging out)."""
        moved = nodes[self.outer] - self.body.points[self.outer]
        return -np.einsum("mni,mni->mn", moved, self.outward)

    def perimeters(self, nodes: np.ndarray) -> np.ndarray:
        """(m,) m: each section's outer polygon perimeter with the nodes at `nodes`."""
        ring = nodes[self.outer]
        return np.linalg.norm(np.roll(ring, -1, axis=1) - ring, axis=2).sum(axis=1)

    def closed_surface(self, nodes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The outer surface at `nodes` closed by a fan over each end section: vertices and outward faces
        (for the exact inside test)."""
        first, last = self.outer[0], self.outer[-1]
        centres = np.stack([nodes[first].mean(axis=0), nodes[last].mean(axis=0)])
        c0, c1 = len(nodes), len(nodes) + 1
        nxt = np.roll(np.arange(first.size), -1)
        cap0 = np.stack([np.full(first.size, c0), first[nxt], first], axis=1)
        cap1 = np.stack([np.full(last.size, c1), last, last[nxt]], axis=1)
        faces = np.concatenate([self.body.faces, cap0, cap1])
        vertices = np.concatenate([nodes, centres])
        if enclosed_volume(vertices, faces) < 0:  # caps wound against the sides: turn them
            faces = np.concatenate([self.body.faces, cap0[:, ::-1], cap1[:, ::-1]])
        return vertices, faces


def limb_tissue(body: Body, segment: str, stations: Stations, hull_radii: np.ndarray,
                materials: Materials | None = None, bones: tuple[np.ndarray, np.ndarray] | None = None) -> LimbTissue:
    """The tissue of the limb under a garment whose stations are `stations` and whose skin sections have
    radii `hull_radii` (M, N) from each station's centre at N even angles (see the module note); bones: the
    rig's bone heads and tails (B, 3) each in the body's posture (default: standing)."""
    if segment not in LIMB_BONES:
        raise HitogataError(f"garment: segment {segment!r} has no limb tissue model; allowed {', '.join(LIMB_BONES)}")
    materials = materials or load_materials()
    m_all, n_all = hull_radii.shape
    chosen = np.unique(np.concatenate([np.arange(0, m_all, ALONG), [m_all - 1]]))
    angles = np.arange(0, n_all, AROUND)
    m, n = len(chosen), len(angles)
    origins, u, v = stations.origins[chosen], stations.u[chosen], stations.v[chosen]
    normal = np.cross(u, v)
    theta = 2 * np.pi * angles / n_all
    ray = np.cos(theta)[None, :, None] * u[:, None] + np.sin(theta)[None, :, None] * v[:, None]  # (m, n, 3)
    outer_points = origins[:, None] + hull_radii[chosen][:, angles, None] * ray
    heads, tails = (body.rig.heads, body.rig.tails) if bones is None else bones
    centres, radii = _bone_axis(body.rig.names, heads, tails, segment, origins, normal)
    # where the bone's axis lies near the skin (the shin, the kneecap) its capsule is narrowed to leave
    # `LEAST_TISSUE` of tissue: the rest of the bone there is the held core
    reach = np.einsum("mni,mni->mn", outer_points - centres[:, None], ray).min(axis=1)
    radii = np.minimum(radii, reach - LEAST_TISSUE)
    if np.min(radii) <= 0:
        worst = int(np.argmin(radii))
        raise HitogataError(f"garment: the limb's bone axis lies {1000 * reach[worst]:.1f} mm from the skin at "
                            f"station {chosen[worst]} of the segment; allowed at least {1000 * LEAST_TISSUE:.0f} mm")
    inner_points = centres[:, None] + radii[:, None, None] * ray
    depth = np.linalg.norm(outer_points - inner_points, axis=2)
    skin = skin_thickness(body.bmi, body.params.sex)
    radial = MUSCLE_LAYERS + SKIN_LAYERS
    tets, i, j, k = annulus_tets(radial, n, m - 1)
    # share of the way from bone to skin of each radial node layer: muscle evenly to the skin layer, then
    # the skin layer evenly (at most half the tissue on each ray)
    share_skin = np.minimum(skin, 0.5 * depth[k, j]) / depth[k, j]
    layer = np.where(i <= MUSCLE_LAYERS, (1 - share_skin) * i / MUSCLE_LAYERS,
                     1 - share_skin * (radial - i) / SKIN_LAYERS)
    nodes = inner_points[k, j] + layer[:, None] * (outer_points[k, j] - inner_points[k, j])
    region_skin = i[tets].min(axis=1) >= MUSCLE_LAYERS
    E = np.where(region_skin, materials.regions["skin"].E, materials.regions["muscle"].E)
    nu = np.where(region_skin, materials.regions["skin"].nu, materials.regions["muscle"].nu)
    stiffness = sp.csr_matrix(stiffness_matrix(nodes, tets, E, nu))
    fixed = np.zeros((len(nodes), 3), dtype=bool)
    fixed[i == 0] = True
    for end in (0, m - 1):  # the end sections held along the limb (its largest axis component)
        fixed[k == end, int(np.argmax(np.abs(normal[end])))] = True
    faces, _ = boundary_faces(tets)
    faces = faces[(i[faces] == radial).all(axis=1)]
    outer = np.full((m, n), -1)
    on = i == radial
    outer[k[on], j[on]] = np.flatnonzero(on)
    return LimbTissue(ContactBody(nodes, faces, stiffness, fixed.ravel()), tets, chosen, outer, ray, k)


def _bone_axis(names: tuple[str, ...], heads: np.ndarray, tails: np.ndarray, segment: str,
               origins: np.ndarray, normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Where the limb's bone axis crosses each station's plane (m, 3) and the bone's capsule radius there
    (m,): the right limb's bones (head → tail lines), the crossing nearest the station's centre."""
    bones = [b for b, name in enumerate(names) if name.endswith(".R") and name.startswith(LIMB_BONES[segment])]
    centres, radii = [], []
    for origin, n in zip(origins, normal):
        best = (np.inf, origin, 0.0)
        for b in bones:
            head, tail = heads[b], tails[b]
            along = float((tail - head) @ n)
            t = float((origin - head) @ n) / along if abs(along) > 1e-9 else 0.0
            t = min(max(t, 0.0), 1.0)
            point = head + t * (tail - head)
            point = point - float((point - origin) @ n) * n  # into the station's plane
            distance = float(np.linalg.norm(point - origin))
            if distance < best[0]:
                best = (distance, point, bone_radius(names[b]))
        centres.append(best[1])
        radii.append(best[2])
    return np.array(centres), np.array(radii)

