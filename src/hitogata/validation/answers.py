"""hitogata's answer to each validation row, on the skinned and on the elastic surface.

Each study's subjects become a body (sex, age, stature and mass as reported:
the missing ones the default body's; a mixed group is the mean of a female
and a male body). Then, by kind:

- posture_change: the measurement (`hitogata.measure`) in the posture minus
  standing (the moved joints at their clinical zero: `standing_row`), on the
  skinned surface (DQS) and on the elastic whole body held in each posture
  with its skin's self-contact resolved (`skin.single_pose.elastic_pose`);
- skin_strain: the zone's area-weighted mean stretch, from standing, of short
  skin lines drawn along the limb or trunk (vertical) or round it
  (horizontal), or its area change (`measure.strain`), on both surfaces;
- frequency, damping: the region's soft-tissue resonance of the elastic whole
  body (`elastic.resonance`); a row of a local probe (a myometer's tap on the
  tissue under it) is undefined: the model's answer is the segment's;
- stiffness: the tissue region's modulus (muscle: the muscle region; fat: the
  skin-and-fat layer); the dermis alone is no region of the model: undefined;
- pressure, where the study gives its garment's size and fabric (`validation.pressure`): on the
  skinned surface Laplace's estimate on the rigid tape (`garment.pressure`), on the elastic surface the
  contact garment dressed on the soft body (`garment.contact`).

An answer that has no meaning is `Answer.undefined` with the reason, never a
number.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

import numpy as np

from hitogata.body.model import Body, default_measurements
from hitogata.elastic.materials import Materials, load_materials
from hitogata.errors import HitogataError
from hitogata.geometry.normals import triangle_normals, vertex_normals
from hitogata.measure.zones import BackZone, JointZone
from hitogata.posing.names import resolve_dofs
from hitogata.posing.pose import poser_for
from hitogata.skeleton.stretches import spread
from hitogata.validation.dataset import RESONANT, Dataset, Row, Source, Subjects
from hitogata.validation.pressure import (
    NO_FABRIC,
    contact_garment,
    contact_pressure,
    covered_levels,
    dress_row_garment,
    laplace_level,
    row_fabric,
)

SURFACES = ("skinned", "elastic")
MODEL_ELEMENT_SIZE = 40.0  # mm: the whole body's lattice, as a held posture's (`skin.single_pose`)
RESONANCE_MODES = 60  # the lowest modes searched for a region's resonance (2-8 Hz on the default bodies)
BOTH_SEXES = ("female", "male")
PROBE_REASON = ("a {probe}'s tap rings the tissue under its probe (a local oscillation, ~15 Hz on a relaxed thigh), "
                "not the segment's soft tissue moving on its skeleton after an impact, which the model computes")
# Skin the studies mark that no garment zone covers: the lumbar skin of the Schober test (backward-facing,
# mainly following the lumbar vertebrae).
EXTRA_ZONES = {"lower_back": BackZone(("spine04", "spine05"), facing=0.5)}
# The side of a flexing joint whose skin stretches (rest pose, unit vector): the kneecap faces forward, the
# point of the elbow backward (the arms hang at the sides).
EXTENSOR_SIDE = {"knee": np.array([0.0, 0.0, 1.0]), "elbow": np.array([0.0, 0.0, -1.0])}


@dataclass(frozen=True)
class Answer:
    """The model's value in the row's unit, or None with the reason it has none."""

    value: float | None
    reason: str = ""

    @staticmethod
    def undefined(reason: str) -> Answer:
        return Answer(None, reason)


@dataclass(frozen=True)
class RowAnswers:
    """A row's answers by surface ('skinned', 'elastic'); material rows have the elastic one only."""

    row: Row
    answers: Mapping[str, Answer]


@dataclass
class BodyCache:
    """Bodies built once per subject group, and their postures solved once per posture. A body some row asks
    the resonance of is given its modes when its elastic model is first built (`resonant`)."""

    materials: Materials
    element_size: float = MODEL_ELEMENT_SIZE  # mm, the whole body's lattice
    resonant: set[tuple] = field(default_factory=set)
    bodies: dict[tuple, Body | HitogataError] = field(default_factory=dict)
    modes: dict[int, int] = field(default_factory=dict)  # id(body) → modes its elastic model needs (resonance rows' bodies)
    postures: dict[tuple, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)
    garments: dict[tuple, object] = field(default_factory=dict)  # (body, contact garment) → solve or its error
    covered: dict[str, tuple[str, ...]] = field(default_factory=dict)  # pressure row id → its garment's levels

    def body(self, sex: str, subjects: Subjects) -> Body:
        key = (sex, subjects)
        if key not in self.bodies:
            try:
                built = self.bodies[key] = _build_body(sex, subjects)
                if key in self.resonant:
                    self.modes[id(built)] = RESONANCE_MODES
            except HitogataError as err:
                self.bodies[key] = err
        made = self.bodies[key]
        if isinstance(made, HitogataError):
            raise made
        return made

    def dynamics(self, body: Body):
        """The body's whole elastic model for held postures (with its modes where a row needs them)."""
        from hitogata.skin.single_pose import elastic_dynamics

        return elastic_dynamics(body, self.element_size, self.materials, n_modes=self.modes.get(id(body), 0))


def _build_body(sex: str, subjects: Subjects) -> Body:
    stature, mass = default_measurements(sex)
    if subjects.stature is not None and subjects.mass is None:  # the default body's BMI at the study's stature
        mass = mass * (subjects.stature / stature) ** 2
    return Body.from_measurements(sex, subjects.age or 30.0, subjects.stature or stature,
                                  subjects.mass or mass)


SPINE_STRETCHES = ("lumbar", "thoracic", "spine")  # the posture names that bend a stretch of the spine


def clinical_posture(row: Row, known: tuple[str, ...], where: str, skeleton=None) -> dict[str, float]:
    """The row's posture as clinical angles (radians) by DOF name, names resolved as the command line's.
    'lumbar.flexion', 'thoracic.flexion' and 'spine.flexion' (both) bend a stretch of the spine by the
    angle given, shared among its vertebrae in proportion to their ranges (a Schober test's forward bend)."""
    out: dict[str, float] = {}
    for name, degrees in row.posture.items():
        part, _, dof = name.partition(".")
        if part in SPINE_STRETCHES and skeleton is not None:
            shares = spread(skeleton, part, dof, math.radians(degrees), f"{where}: {name}")
            out.update({n: float(skeleton.rest[skeleton.dof_index(n)]) + a for n, a in shares.items()})
            continue
        for resolved in resolve_dofs(name, known, where):
            out[resolved] = math.radians(degrees)
    return out


def answer_dataset(dataset: Dataset, materials: Materials | None = None, surfaces: Iterable[str] = SURFACES,
                   progress=None, element_size: float = MODEL_ELEMENT_SIZE) -> list[RowAnswers]:
    """Every row's answers, in the dataset's order (rows of one body and posture share their solves);
    `element_size` (mm): the elastic whole body's lattice."""
    cache = BodyCache(load_materials() if materials is None else materials, element_size)
    cache.resonant = {(sex, dataset.source_of(r).subjects) for r in dataset.rows if r.kind in RESONANT and not r.probe
                      for sex in sexes(dataset.source_of(r).subjects)}
    cache.covered = covered_levels(dataset)
    surfaces = tuple(surfaces)
    out = []
    for k, row in enumerate(dataset.rows):
        out.append(RowAnswers(row, answer_row(row, dataset.source_of(row), cache, surfaces)))
        if progress is not None:
            progress(k + 1, len(dataset.rows), row)
    return out


def answer_row(row: Row, source: Source, cache: BodyCache, surfaces: tuple[str, ...]) -> dict[str, Answer]:
    """One row's answers by surface; a body the model cannot build is an undefined answer with the reason."""
    groups = sexes(source.subjects)
    wanted = ("elastic",) if row.kind in ("frequency", "damping", "stiffness") else surfaces
    per_sex: dict[str, list[Answer]] = {s: [] for s in wanted}
    for sex in groups:
        try:
            body = cache.body(sex, source.subjects)
        except HitogataError as err:
            return {s: Answer.undefined(f"the study's subjects: {err}") for s in wanted}
        for surface in wanted:
            per_sex[surface].append(_one(row, body, surface, cache))
    return {s: _mean(answers) for s, answers in per_sex.items()}


def sexes(subjects: Subjects) -> tuple[str, ...]:
    """A mixed group is answered as the mean of a female and a male body."""
    return BOTH_SEXES if subjects.sex == "mixed" else (subjects.sex,)


def _mean(answers: list[Answer]) -> Answer:
    missing = [a for a in answers if a.value is None]
    if missing:
        return missing[0]
    return Answer(float(np.mean([a.value for a in answers])))


def _one(row: Row, body: Body, surface: str, cache: BodyCache) -> Answer:
    if row.kind == "stiffness":
        return _stiffness(row, cache.materials)
    if row.kind in RESONANT:
        return _resonance(row, body, cache)
    if row.kind == "pressure":
        if row_fabric(row) is None:
            return Answer.undefined(NO_FABRIC)
        if surface == "elastic":
            return _contact(row, body, cache)
    skin, joints = _posture(row, body, surface, cache)
    if row.kind == "pressure":
        return _pressure(row, body, skin, joints)
    standing = _posture(standing_row(row), body, surface, cache)
    if row.kind == "posture_change":
        return _posture_change(row, body, standing, (skin, joints))
    return _skin_strain(row, body, standing[0], skin)


def standing_row(row: Row) -> Row:
    """The row's standing posture, what its change is measured from: the joints it moves at their clinical zero
    (the anatomical position a study's subject stands in: knees straight, arms hanging at the sides), the others
    as the body stands. Not the body's rest pose: MakeHuman's holds the arms abducted about 42° and the knees
    flexed 9°, so a change from it would count the arms coming down as part of a lift."""
    return dataclasses.replace(row, posture=dict.fromkeys(row.posture, 0.0))


def _posture(row: Row, body: Body, surface: str, cache: BodyCache) -> tuple[np.ndarray, np.ndarray]:
    """(skin, rig joints) of the body in the row's posture on a surface; each posture solved once."""
    poser = poser_for(body)
    from hitogata.skeleton.shoulder import channel_names

    known = poser.skeleton.dof_names + channel_names(poser.skeleton)
    clinical = clinical_posture(row, known, f"row {row.id!r}: posture", poser.skeleton)
    key = (id(body), surface, tuple(sorted(clinical.items())))
    if key not in cache.postures:
        if surface == "skinned" or not clinical:
            posed = poser.pose(clinical=clinical, skinning="dqs")
            skin = posed.vertices
        else:
            from hitogata.skin.single_pose import elastic_pose

            held = elastic_pose(cache.dynamics(body), clinical=clinical, contact=True)
            posed, skin = held.posed, held.vertices
        cache.postures[key] = (skin, posed.rig_joints)
    return cache.postures[key]


def _posture_change(row: Row, body: Body, standing_posture: tuple[np.ndarray, np.ndarray],
                    posture: tuple[np.ndarray, np.ndarray]) -> Answer:
    """The change of the row's measurement from standing (`standing_row`) to the posture, each (skin, joints)."""
    from hitogata.measure.measurements import measure
    from hitogata.measure.values import UNDEFINED_BECAUSE

    standing = measure(body, *standing_posture).get(row.quantity)
    posed = measure(body, *posture).get(row.quantity)
    if not (math.isfinite(standing) and math.isfinite(posed)):
        why = UNDEFINED_BECAUSE.get(row.quantity, "ISO 8559-1 defines it standing")
        return Answer.undefined(f"{row.quantity} has no meaning in this posture ({why})")
    change = posed - standing
    return Answer(100.0 * change if row.unit == "cm" else 100.0 * change / standing)


def _skin_strain(row: Row, body: Body, standing: np.ndarray, skin: np.ndarray) -> Answer:
    """The skin's stretch from standing (`standing_row`'s skin) to the posture's, over the row's zone: the mean
    area change, or the stretch of lines drawn along or round the limb or trunk (their directions found on the
    rest skin, taken into each standing triangle's plane)."""
    from hitogata.measure.strain import directional_stretch, skin_strain
    from hitogata.measure.zones import ZONES, body_zones, zone_faces

    zone, _, direction = row.quantity.partition(".")
    spec: JointZone | BackZone
    if zone in EXTRA_ZONES:
        spec = EXTRA_ZONES[zone]
        faces = body.faces[zone_faces(body, spec)]
    else:
        name = zone if zone in ZONES else f"{zone}_right"
        spec, faces = ZONES[name], body.faces[body_zones(body)[name]]
    if zone in EXTENSOR_SIDE:  # the skin over the kneecap or the point of the elbow, where the studies mark it
        faces = faces[vertex_normals(body.vertices, body.faces)[faces].mean(axis=1) @ EXTENSOR_SIDE[zone] > 0.5]
    if direction == "area":
        strain = skin_strain(standing, skin, faces)
        weights = strain.rest_area
        return Answer(100.0 * float(np.sum(weights * strain.area_ratio) / weights.sum() - 1.0))
    directions, weights = _zone_directions(body, faces, spec, direction)
    stretch = directional_stretch(standing, skin, faces, directions)
    good = np.isfinite(stretch)
    return Answer(100.0 * float(np.average(stretch[good] - 1.0, weights=weights[good])))


def _zone_directions(body: Body, faces: np.ndarray, zone, direction: str) -> tuple[np.ndarray, np.ndarray]:
    """Per face, the rest direction of a line drawn along the limb or trunk ('vertical') or round it
    ('horizontal'), and the face's rest area."""
    tri = body.vertices[faces]
    normal = triangle_normals(tri)
    area = 0.5 * np.linalg.norm(normal, axis=1)
    normal /= np.maximum(2.0 * area, 1e-30)[:, None]
    axis = np.array([0.0, 1.0, 0.0])
    if isinstance(zone, JointZone):  # along the limb: the mean of the two bones meeting at the joint
        rig = body.rig
        k = rig.index(zone.joint)
        parent = rig.index(zone.bones[0])
        child = rig.index(zone.bones[-1])
        axis = (rig.heads[k] - rig.heads[parent]) / np.linalg.norm(rig.heads[k] - rig.heads[parent])
        axis += (rig.tails[child] - rig.heads[k]) / np.linalg.norm(rig.tails[child] - rig.heads[k])
    along = axis - (normal @ axis)[:, None] * normal
    along /= np.maximum(np.linalg.norm(along, axis=1), 1e-30)[:, None]
    return (along if direction == "vertical" else np.cross(normal, along)), area


DERMIS = ("the dermis is no region of its own: the model's skin region is skin and subcutaneous fat as one "
          "layer (compare the fat rows)")


def stiffness_region(row: Row) -> str | None:
    """The model region a stiffness row measures ('muscle', or 'skin': the skin-and-fat layer, for fat), None for
    the dermis alone, which is no region of the model (its answer is undefined, and identification fits no such
    row)."""
    tissue = row.quantity.split(".")[0]
    if tissue == "skin":
        return None
    return "muscle" if tissue == "muscle" else "skin"


def stiffness_value(row: Row, youngs_modulus: float, poissons_ratio: float) -> float:
    """A stiffness row's model value (kPa) from its region's Young's modulus (Pa) and Poisson's ratio: the
    modulus itself, or the shear modulus E / 2(1 + ν), as the row's quantity names it."""
    modulus = row.quantity.split(".")[1]
    value = youngs_modulus if modulus == "youngs_modulus" else youngs_modulus / (2.0 * (1.0 + poissons_ratio))
    return value / 1000.0


def _stiffness(row: Row, materials: Materials) -> Answer:
    region = stiffness_region(row)
    if region is None:
        return Answer.undefined(DERMIS)
    m = materials.regions[region]
    return Answer(stiffness_value(row, m.E, m.nu))


def unresolved_region(row: Row, volume, body: Body, element_size: float) -> str:
    """Why a resonance row's region is not the model's ('' where it is): its tissue elements fill less than
    `elastic.resonance.MIN_COVERAGE` of it on this body (`volume`: the body's tissue mesh)."""
    from hitogata.elastic.resonance import MIN_COVERAGE, body_region_coverage

    coverage = body_region_coverage(volume, body.rig, body.vertices, row.quantity)
    if coverage >= MIN_COVERAGE:
        return ""
    return (f"the elastic model's {element_size:g} mm lattice fills {100 * coverage:.0f} % of this body's "
            f"{row.quantity.replace('_', ' ')} ({100 * MIN_COVERAGE:.0f} % needed): its soft tissue is not modelled "
            "there")


def _resonance(row: Row, body: Body, cache: BodyCache) -> Answer:
    from hitogata.elastic.model import bone_segments
    from hitogata.elastic.resonance import region_nodes, resonance

    if row.probe:
        return Answer.undefined(PROBE_REASON.format(probe=row.probe))
    model = cache.dynamics(body).model
    unresolved = unresolved_region(row, model.volume, body, cache.element_size)
    if unresolved:
        return Answer.undefined(unresolved)
    heads, tails = bone_segments(model.volume, body.rig)
    nodes = region_nodes(model.points, model.volume.bone_names, heads, tails, row.quantity)
    found = resonance(model.M, model.modes.eigenvalues, model.modes.vectors, nodes, model.alpha, model.beta,
                      row.quantity)
    if row.kind == "frequency":
        return Answer(found.frequency)
    if row.unit == "1":
        return Answer(found.damping_ratio)
    return Answer(found.damping_ratio * 2.0 * math.pi * found.frequency)  # decay rate ζω (1/s)


def _pressure(row: Row, body: Body, skin: np.ndarray, joints: np.ndarray) -> Answer:
    from hitogata.garment.pressure import MMHG

    return Answer(laplace_level(row, body, skin, joints).mean_pressure / MMHG)


def _contact(row: Row, body: Body, cache: BodyCache) -> Answer:
    """The contact garment's answer at the row's level; one solve per body and garment."""
    if row.posture:
        return Answer.undefined("the contact garment is dressed on the standing body; this posture has "
                                "Laplace's answer only")
    where = f"row {row.id!r}"
    try:
        garment = contact_garment(row, body, cache.covered.get(row.id, (row.quantity,)), where)
        key = (id(body), garment)
        if key not in cache.garments:
            try:
                cache.garments[key] = dress_row_garment(body, garment, cache.materials, where)
            except HitogataError as err:
                cache.garments[key] = err
        solved = cache.garments[key]
        if isinstance(solved, HitogataError):
            raise solved
        return Answer(contact_pressure(solved, row.quantity))
    except HitogataError as err:
        return Answer.undefined(f"the contact garment: {err}")


def reachable(dataset: Dataset, body: Body) -> None:
    """A one-line error for the first posture the skeleton cannot take (names, ranges), before any work."""
    from hitogata.skeleton.shoulder import channel_names

    poser = poser_for(body)
    known = poser.skeleton.dof_names + channel_names(poser.skeleton)
    for row in dataset.rows:
        if not row.posture:
            continue
        where = f"{dataset.path}: row {row.id!r}: posture"
        try:
            clinical = clinical_posture(row, known, where, poser.skeleton)
            poser.angles(clinical=clinical, on_limit="raise")
        except HitogataError as err:
            text = str(err)
            raise HitogataError(text if text.startswith(where) else f"{where}: {text}; the model cannot reach it"
                                ) from None
