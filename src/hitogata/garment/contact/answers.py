"""The answers of a dressed garment: pressure at the levels and on the skin, the garment's strain, the hold.

At each level the pressure is the skin's push on the garment's rings within `BAND` of the level's
plane over their area (`readings`, which Newton watches too; the fabric lies within the barrier's
reach, a fraction of a millimetre, of the skin: its area is the skin's under it to better than 1 %):
the mean round the girth that RAL-GZ 387/1 classifies a stocking by at B. Round a whole ring that mean is 2π T / C by the ring's balance, whatever
the section's shape; it differs from Laplace's quick estimate (`garment.pressure`, the same relaxed
size and course fabric on the standing body) by the tension and circumference the fabric really takes.
Where the pressure goes round the ring is the contact's own answer: `peak` is the largest of the
sensor pressures (`sensor_pressure`) of the level's skin within `BAND` of its plane. The garment's
course strain is its ring's at the level, the wale's the mean of the faces beside it; its circumference
is the ring's. The hold is the friction coefficient the skin must supply there to keep the courses at
their level: the force holding them over the force pressing. After the solve two exact checks: no
garment vertex inside the body (winding number of the closed skin) and no garment triangle through a
skin triangle (the IPC Toolkit's intersection test).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.sparse as sp

from hitogata.body.model import Body
from hitogata.elastic.materials import Materials
from hitogata.garment.contact.dressing import Dressing, dress
from hitogata.garment.contact.equilibrium import crossings
from hitogata.garment.contact.pressure import pressing_forces
from hitogata.garment.contact.readings import BAND, LevelReader
from hitogata.garment.contact.spec import GarmentSpec, load_garment
from hitogata.garment.levels import LEVELS
from hitogata.garment.pressure import MMHG, Garment, compression_class, garment_pressure
from hitogata.geometry.mesh_checks import contains
from hitogata.measure.sections import tape_girth
from hitogata.geometry.topology import topology

RAL_LETTERS = {"ankle": "B", "calf": "C", "knee": "E", "thigh": "G"}


@dataclass(frozen=True)
class LevelContact:
    """One level: mean pressure (Pa) by contact and by Laplace (NaN where Laplace has no such level), the
    contact's peak (Pa), the body's girth (m), the garment's circumference there (m), its course and wale
    strain, the friction coefficient holding it; on the soft body the indentation (m: mean and largest
    round the level) and the body's girth under the garment (m)."""

    level: str
    pressure: float
    laplace: float
    peak: float
    girth: float
    garment_girth: float
    course_strain: float
    wale_strain: float
    hold: float
    indentation: float = float("nan")  # m: the skin's mean move in under the garment (NaN: rigid body)
    deepest: float = float("nan")  # m: the largest move in round the level (< 0: the skin bulges out)
    girth_under: float = float("nan")  # m: the body's girth under the garment (NaN: rigid body)

    def as_row(self) -> dict[str, float | str]:
        """The level's figures at the user's edge: mmHg, Pa, cm, %."""
        return {"level": self.level, "ral_level": RAL_LETTERS.get(self.level, ""),
                "pressure_mmHg": self.pressure / MMHG, "pressure_Pa": self.pressure,
                "laplace_mmHg": self.laplace / MMHG, "peak_mmHg": self.peak / MMHG, "girth_cm": 100 * self.girth,
                "garment_girth_cm": 100 * self.garment_girth, "course_strain_pct": 100 * self.course_strain,
                "wale_strain_pct": 100 * self.wale_strain, "friction_needed": self.hold,
                "indentation_mm": 1000 * self.indentation, "deepest_mm": 1000 * self.deepest,
                "girth_under_cm": 100 * self.girth_under}


@dataclass(frozen=True, eq=False)
class GarmentContact:
    """The garment's contact answers on one body: its levels, the skin (V, 3) and faces, the pressure map
    (V,) Pa (0 off the garment), the skin under the garment (V,) bool, the garment's vertices and faces, each
    garment face's course and wale strain, the RAL-GZ 387/1 class at the ankle (None without an ankle
    level), and the checks after the solve: garment vertices inside the body (count), whether garment and
    skin cross, the least garment–skin distance (m), Newton's iterations and whether they converged."""

    title: str
    levels: tuple[LevelContact, ...]
    skin: np.ndarray
    faces: np.ndarray
    pressure: np.ndarray
    under: np.ndarray
    garment: np.ndarray
    garment_faces: np.ndarray
    course_strain: np.ndarray
    wale_strain: np.ndarray
    compression_class: str | None
    inside: int
    crossing: bool
    min_distance: float
    iterations: int
    converged: bool


def sensor_pressure(points: np.ndarray, faces: np.ndarray, force: np.ndarray) -> np.ndarray:
    """(N,) Pa: each node's pressing force and its neighbours' over their areas (a sensor the size of a
    node's ring of triangles)."""
    pressing, areas = pressing_forces(points, faces, force)
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    n = len(points)
    ring = sp.csr_matrix((np.ones(2 * len(edges)), (np.concatenate([edges[:, 0], edges[:, 1]]),
                                                     np.concatenate([edges[:, 1], edges[:, 0]]))), shape=(n, n))
    ring = (ring > 0).astype(float) + sp.identity(n)
    pooled = ring @ areas
    out = np.zeros(n)
    on = pooled > 0
    out[on] = (ring @ pressing)[on] / pooled[on]
    return out


def garment_contact(dressing: Dressing, laplace: bool = True) -> GarmentContact:
    """The answers of a solved dressing (see the module note); laplace: Laplace's estimate beside them (on
    the standing body: a motion's frames leave it NaN)."""
    body, spec, tube = dressing.body, dressing.spec, dressing.tube
    skin, faces = dressing.skin, body.faces
    pressing, _ = pressing_forces(skin, faces, dressing.force)
    holding = np.linalg.norm(dressing.friction, axis=1)
    sensor = sensor_pressure(skin, faces, dressing.force)
    reader = LevelReader.build(tube, dressing.arc, dressing.level_arc, dressing.tissue)
    pressures = reader.pressures(dressing.garment, dressing.garment_force)
    stations = tube.stations
    axis = stations.axis
    under = dressing.contact_skin & ((skin - stations.origins[0]) @ axis[0] >= 0) \
        & ((skin - stations.origins[-1]) @ axis[-1] <= 0)
    quick = _laplace(dressing) if laplace else {}
    _, wale = tube.membrane.strains(dressing.garment)
    ring_strain = tube.ring_strains(dressing.garment)
    ring_of_face = tube.faces[:, 0] // tube.per_ring
    topo = topology(faces)
    rows = []
    for k, (level, at) in enumerate(zip(dressing.levels, dressing.level_arc)):
        band = under & level.skin & (np.abs((skin - level.origin) @ level.normal) < BAND)
        ring = int(np.argmin(np.abs(dressing.arc - at)))
        standing = tape_girth(skin, topo, level.origin, level.normal, level.origin, part=level.skin)
        pressed = float(pressing[band].sum())
        soft = _soft_level(dressing, reader, k, standing.girth)
        rows.append(LevelContact(level.name, float(pressures[k]),
                                 quick.get(level.name, np.nan), float(sensor[band].max()) if band.any() else np.nan,
                                 standing.girth, float(tube.relaxed[ring] * (1 + ring_strain[ring])),
                                 float(ring_strain[ring]), float(wale[np.abs(ring_of_face - ring) <= 1].mean()),
                                 float(holding[band].sum()) / pressed if pressed > 0 else np.nan, *soft))
    ankle = next((row for row in rows if row.level == "ankle"), None)
    course, _ = tube.membrane.strains(dressing.garment)
    if dressing.tissue is None or dressing.tissue_nodes is None:
        pressed_on, pressed_faces = skin, faces[dressing.contact_skin[faces].all(axis=1)]
        inside = int(contains(skin, faces, dressing.garment).sum())
    else:  # the soft limb's surface as solved
        pressed_on, pressed_faces = dressing.tissue_nodes, dressing.tissue.body.faces
        inside = int(contains(*dressing.tissue.closed_surface(dressing.tissue_nodes), dressing.garment).sum())
    return GarmentContact(spec.title, tuple(rows), skin, faces,
                          np.where(under, sensor, 0.0), under,
                          dressing.garment, tube.faces, course, wale,
                          None if ankle is None else compression_class(ankle.pressure),
                          inside, crossings(dressing.garment, tube.faces, pressed_on, pressed_faces), dressing.min_distance,
                          dressing.iterations, dressing.converged)


def dress_garment(body: Body, garment: GarmentSpec | str | Path, soft: bool = True,
                  materials: Materials | None = None) -> GarmentContact:
    """A garment (a checked `GarmentSpec`, a shipped garment's name or a garment file) put on the standing
    body and solved: its contact answers. soft: on a limb, the tissue (of `materials`, default the
    literature's) takes the garment's loads (the indentation and the girths under the garment); else the
    skin is rigid."""
    spec = garment if isinstance(garment, GarmentSpec) else load_garment(garment)
    return garment_contact(dress(body, spec, soft, materials))


def _soft_level(dressing: Dressing, reader: LevelReader, k: int, girth: float) -> tuple[float, float, float]:
    """At the soft limb's section nearest the `k`th level: the mean and largest indentation (m) and the body's
    girth under the garment (the standing girth less the section's shrinking, m); NaN on the rigid body."""
    tissue, nodes = dressing.tissue, dressing.tissue_nodes
    if tissue is None or nodes is None:
        return float("nan"), float("nan"), float("nan")
    mean, deepest = reader.indentations(nodes)
    section = int(reader.sections[k])
    shrink = float(tissue.perimeter[section] - tissue.perimeters(nodes)[section])
    return float(mean[k]), float(deepest[k]), girth - shrink


def _laplace(dressing: Dressing) -> dict[str, float]:
    """Laplace's mean pressure (Pa) at the garment's levels Laplace knows, on the standing body."""
    spec = dressing.spec
    known = tuple(level for level in spec.levels if level in LEVELS)
    if not known:
        return {}
    if spec.mesh is not None:  # the mesh's relaxed circumference at the levels
        relaxed = np.interp(dressing.level_arc, dressing.arc, dressing.tube.relaxed)
        garment = Garment(relaxed={level: float(c) for level, c in zip(spec.levels, relaxed) if level in known})
    elif spec.relaxed is not None:
        garment = Garment(relaxed={level: spec.relaxed[level] for level in known})
    else:
        garment = Garment(ease=spec.ease, levels=known)
    return {name: row.mean_pressure for name, row in garment_pressure(dressing.body, garment, spec.course).items()}
