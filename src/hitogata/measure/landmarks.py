"""Landmarks of ISO 8559-1 on the body surface: fixed vertices and points between them.

Every body shares the MakeHuman mesh's topology, and its shape targets keep a
vertex on the same anatomical point in every shape. So a landmark on a
profile of the trunk is found once, on the reference body (MakeHuman's
default female shape), and is the same vertex on every body: it moves
continuously with the shape parameters and follows the skin into any
posture. Found anew on each body, such landmarks jumped between vertices as
the shape changed (the male cervicale dropped 16 mm between BMI 20 and 22;
the male under-breast point wandered 4–18 cm and fell to the navel on lean
men, where the girth was lost). The bony points of the limbs depend on the
limbs' build (a broad male shoulder puts the female's acromion vertex inside
the shoulder joint), so they are found on each body, as the exact points
where their rays cross the skin (`surface_points.SurfacePoint`), which move
continuously with the shape. Each rule below finds
its vertex on the rest surface from the rig's joint centres
(docs/measurements.md):

- bony points of the limbs (acromion, olecranon, ulnar styloid), on each
  body: the first skin hit of a ray from the joint centre in the direction
  of that bone point;
- cervicale and the back at the navel's height, on each body: where a ray
  straight backwards from the base neck joint (from the spine at the navel's
  height) leaves the skin, an exact point (from the reference's vertices the male back
  waist length read 4.3 cm short);
- the bust point and the navel: where they are pronounced on the reference
  (the most forward vertex of the breast; the deepest dip of the front
  midline profile): a male chest has no forward-most nipple, but the same
  vertex is his nipple;
- points on a profile (under-breast fold, crotch, buttock): from the
  reference's profiles;
- the thigh level (a fraction along the femur): from each body's own crotch
  vertex and joints, so it too varies continuously;
- levels where a part is narrowest (ISO 8559-1's waist: the natural waistline
  between the lowest rib and the iliac crest, which a surface cannot show, so
  the trunk's narrow part between the navel and the inframammary fold; the
  neck girth's, just below the larynx, where the neck is narrowest), as soft
  minima of sampled girths (`soft_least`), so that they move continuously;
  and the points a tape passes there (waist front, back and side; the neck's
  base: jugular notch and side neck point), on each body;
- the armpit fold points and the axilla level (`armpits`), on each body;
- the iliac crest (iliocristale), on each body: the crest's height from the
  rig's hip joints and base neck joint (`LEVEL_ILIAC_CREST` of that span,
  Drillis & Contini's proportions), where the midaxillary line (midway
  between the right armpit's front and back folds) meets the right flank.
  No surface shows the crest (a heavy flank hides it), and the rig's
  joints move continuously with the shape; its height is checked against
  ANSUR II's iliocristale height (docs/measurements.md).

The navel (omphalion) keeps the girth ANSUR II calls its waist
circumference (`omphalion_waist_girth`) and the end of the back waist length.

Limbs are measured on the right side, as ISO 8559-1 and ISO 7250-1 prescribe.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields
from functools import cache
from typing import Any

import numpy as np

from hitogata.body.model import Body
from hitogata.errors import HitogataError
from hitogata.measure.axes import UP, JointSet, axis, trunk_frame, unit
from hitogata.measure.armpits import FOLD_ABOVE, armpit_points, at_height
from hitogata.measure.levels import ANKLE_SPAN, CALF_SPAN, extreme_girth_level
from hitogata.measure.raycast import first_hit
from hitogata.measure.sections import section, tape_girth
from hitogata.measure.surface_points import FaceSearch, SurfacePoint
from hitogata.geometry.topology import Topology, topology
from hitogata.body.shape import ShapeParameters
from hitogata.geometry.rotations import shortest_arc
from hitogata.volume.anatomy import LEVEL_ILIAC_CREST

MIDLINE_TOLERANCE = 1e-3  # m: vertices this close to x = 0 lie on the body's midline
ACROMION_TILT = 0.35  # lateral run per unit rise of the ray from the shoulder joint (≈ 19°)
NAVEL_REACH = 0.03  # m: the navel dips below the front profile's chord over ± this height
THIGH_BELOW_CROTCH = 0.01  # m: the thigh girth plane passes this far below the crotch
FORWARD = np.array([0.0, 0.0, 1.0])  # the body's front (+Z)
# Midline rays start this far to the side: the symmetric mesh has edges on the midline, which a
# ray along it would graze (a miss by round-off); 0.01 mm moves the point by as much.
OFF_MIDLINE = np.array([1e-5, 0.0, 0.0])
CHEST_FRONT = 0.12  # m: the chest's front profile lies within this depth behind the bust point
LATERAL = np.array([1.0, 0.0, 0.0])  # the body's left (+X)
WAIST_SAMPLES = 12  # horizontal girths sampled from the navel to the inframammary fold
WAIST_SOFTNESS = 0.01  # m of girth: the level is the middle of the trunk's narrow part (`soft_least`)
NECK_SPAN = (0.0, 0.8)  # fractions of the base neck joint → head joint searched for the narrowest neck
NECK_SAMPLES = 9
NECK_SOFTNESS = 0.002  # m of girth
FRONT_NECK_SPAN = (-0.10, 0.03)  # m about the base neck joint's height: searched for the jugular notch
FRONT_NECK_SAMPLES = 27
FRONT_NECK_SOFTNESS = 0.002  # m of depth
SIDE_NECK_SOFTNESS = 0.001  # m of depth below the neck-to-shoulder chord
PELVIS_ORIGIN = "root"  # the joint the pelvis carries the crotch from (`pelvis_point`)
GIRDLE_JOINTS = {side: (f"clavicle.{side}", f"upperarm01.{side}") for side in "RL"}  # sternoclavicular, glenohumeral


@dataclass(frozen=True)
class Landmarks:
    """One body's landmarks (vertex indices and points between them) and the levels of its
    girths and widths."""

    head_top: int
    cervicale: SurfacePoint
    front_neck: SurfacePoint  # the jugular notch: the front of the neck's base
    side_neck: SurfacePoint  # right side of the neck's base
    acromion_right: SurfacePoint
    acromion_left: SurfacePoint
    olecranon: SurfacePoint  # right elbow, back
    ulnar_styloid: SurfacePoint  # right wrist, little-finger side
    fold_back_right: SurfacePoint  # armpit fold points (`armpits`)
    fold_back_left: SurfacePoint
    fold_front_right: SurfacePoint
    fold_front_left: SurfacePoint
    back_middle: SurfacePoint  # the back's midline at the folds' level
    front_middle: SurfacePoint  # the chest's midline at the folds' level
    bust_right: int
    bust_left: int
    underbust: int  # right inframammary fold, front
    waist_front: SurfacePoint  # the waist level (ISO 8559-1): front, back, right side
    waist_back: SurfacePoint
    waist_side: SurfacePoint
    omphalion: int  # the navel
    omphalion_back: SurfacePoint  # the back midline at the navel's height
    iliac_crest: SurfacePoint  # right iliocristale: the crest's level on the midaxillary line
    buttock: int  # right buttock, most backward point
    hip_side: SurfacePoint  # right side at the buttock's height
    crotch: int
    thigh_level: float  # fraction of hip → knee where the thigh plane cuts the femur
    # Each acromion's rest position relative to its shoulder joint (m, right then left): the
    # acromion belongs to the shoulder girdle, so a posture carries it with the girdle
    # (`girdle_point`), not with the skin, which MakeHuman binds ~60 % to the humerus there.
    acromion_offsets: tuple[tuple[float, float, float], tuple[float, float, float]]
    # The crotch's rest position relative to the pelvis's frame origin (m): the crotch (the perineum, between
    # the ischiopubic rami) belongs to the pelvis, so a posture carries it with the pelvis (`pelvis_point`), not
    # with the skin, which skinning binds partly to the thighs there (at 90° of hip flexion the crotch vertex
    # slides 15-20 mm forward and up) and the elastic skin draws up between the flexed thighs (5-7 cm).
    crotch_offset: tuple[float, float, float]
    calf_level: float  # fraction of knee → ankle joint where the calf girth is largest
    ankle_level: float  # … where the leg is thinnest above the malleoli
    neck_level: float  # fraction of the base neck joint → head joint where the neck is narrowest
    axilla: float  # height (m) of the armpit at rest


LANDMARK_NAMES = tuple(f.name for f in fields(Landmarks) if f.type in ("int", "SurfacePoint"))


def body_landmarks(body: Body) -> Landmarks:
    """The landmarks of a body, found once on its rest surface (`landmarks_for`) and kept with it."""
    return body.prepared(_find_landmarks)


def _find_landmarks(body: Body) -> Landmarks:
    return landmarks_for(body.vertices, body.faces, JointSet(body.rig.names, body.rig.heads))


def landmarks_for(vertices: np.ndarray, faces: np.ndarray, joints: JointSet) -> Landmarks:
    """A body's landmarks from its rest surface and joints: the reference's trunk vertices, the
    body's own limb points and levels (see the module note)."""
    fixed = reference_vertices_fixed()
    return Landmarks(**asdict(fixed), **_own(vertices, faces, joints, fixed))


def landmark_positions(marks: Landmarks, vertices: np.ndarray) -> dict[str, np.ndarray]:
    """Each landmark's point (3,) on a surface that shares the body's vertices."""
    points = {}
    for name in LANDMARK_NAMES:
        mark = getattr(marks, name)
        points[name] = mark.at(vertices) if isinstance(mark, SurfacePoint) else np.asarray(vertices)[mark]
    return points


@cache
def reference_vertices_fixed() -> FixedVertices:
    """The landmark vertices, found once on the reference body (MakeHuman's default female);
    the body's own points and levels are found on each body (`_own`)."""
    reference = _reference_body()
    return fixed_vertices(reference.vertices, reference.faces, JointSet(reference.rig.names, reference.rig.heads))


@cache
def _reference_body() -> Body:
    return Body.from_parameters(ShapeParameters(sex=0.0))


def find_landmarks(vertices: np.ndarray, faces: np.ndarray, joints: JointSet) -> Landmarks:
    """Apply the landmark rules to a rest surface and its joint centres."""
    fixed = fixed_vertices(vertices, faces, joints)
    return Landmarks(**asdict(fixed), **_own(vertices, faces, joints, fixed))


def fixed_vertices(vertices: np.ndarray, faces: np.ndarray, joints: JointSet) -> FixedVertices:
    """The rules of the landmarks that are one vertex, applied to a rest surface and its joints."""
    v = vertices
    midline = np.flatnonzero(np.abs(v[:, 0]) < MIDLINE_TOLERANCE)
    bust_right, bust_left, navel = reference_vertices()
    crotch = _crotch(v, midline, joints)
    navel_y = float(v[navel, 1])
    return FixedVertices(
        head_top=int(np.argmax(v[:, 1])),
        bust_right=bust_right,
        bust_left=bust_left,
        underbust=_inframammary_fold(v, faces, bust_right, navel_y),
        omphalion=navel,
        buttock=_buttock(v, float(v[crotch, 1]), navel_y),
        crotch=crotch,
    )


@dataclass(frozen=True)
class FixedVertices:
    """The landmarks that are one vertex of the reference body, the same on every body."""

    head_top: int
    bust_right: int
    bust_left: int
    underbust: int
    omphalion: int
    buttock: int
    crotch: int


def _own(v: np.ndarray, faces: np.ndarray, joints: JointSet, fixed: FixedVertices | Landmarks) -> dict[str, Any]:
    """The landmarks and levels each body has of its own (see the module note)."""
    right, left = _acromion(v, faces, joints, "R"), _acromion(v, faces, joints, "L")
    topo = topology(faces)
    knee, ankle = joints["lowerleg01.R"], joints["foot.R"]
    search = FaceSearch(v[faces])
    armpits = armpit_points(v, faces, topo, joints, search)
    fold_level = float(armpits["axilla"]) + FOLD_ABOVE  # type: ignore[arg-type]
    chest = at_height(joints["spine02"], fold_level)
    cervicale = _cervicale(v, faces, joints)
    front_neck = _front_neck(v, faces, topo, joints)
    neck_level = _neck_level(v, topo, joints)
    waist = at_height(joints["spine03"], _waist_height(v, topo, joints, fixed.omphalion, fixed.underbust))
    waist_front, waist_back = (_ray_point(v, faces, waist + OFF_MIDLINE, way * FORWARD) for way in (1.0, -1.0))
    waist_middle = 0.5 * (waist_front.at(v) + waist_back.at(v))
    return {
        "acromion_right": right,
        "acromion_left": left,
        "olecranon": _olecranon(v, faces, joints),
        "ulnar_styloid": _ulnar_styloid(v, faces, joints),
        "thigh_level": _thigh_level(v, fixed.crotch, joints),
        "cervicale": cervicale,
        "front_neck": front_neck,
        "side_neck": _side_neck(v, faces, topo, joints, neck_level, right, search),
        "neck_level": neck_level,
        **armpits,
        "back_middle": _ray_point(v, faces, chest + OFF_MIDLINE, -FORWARD),
        "front_middle": _ray_point(v, faces, chest + OFF_MIDLINE, FORWARD),
        "waist_front": waist_front,
        "waist_back": waist_back,
        "waist_side": _ray_point(v, faces, waist_middle, -LATERAL),
        "omphalion_back": _back_waist(v, faces, joints, fixed.omphalion),
        "iliac_crest": _iliac_crest(v, faces, joints, armpits),
        "hip_side": _ray_point(v, faces, at_height(joints["spine05"], float(v[fixed.buttock, 1])), -LATERAL),
        "acromion_offsets": _acromion_offsets(v, joints, right, left),
        "crotch_offset": tuple(float(x) for x in v[fixed.crotch] - joints[PELVIS_ORIGIN]),
        "calf_level": extreme_girth_level(v, topo, knee, ankle, CALF_SPAN, largest=True),
        "ankle_level": extreme_girth_level(v, topo, knee, ankle, ANKLE_SPAN, largest=False),
    }


def _waist_height(v: np.ndarray, topo: Topology, joints: JointSet, navel: int, underbust: int) -> float:
    """The waist level at rest: where the trunk is narrowest between the navel and the
    inframammary fold (`soft_least`, horizontal tapes round the spine)."""
    heights = np.linspace(v[navel, 1], v[underbust, 1], WAIST_SAMPLES)
    spine = joints["spine03"]
    girths = [tape_girth(v, topo, at_height(spine, y), UP, at_height(spine, y)).girth for y in heights]
    return soft_least(heights, np.array(girths), WAIST_SOFTNESS)


def _neck_level(v: np.ndarray, topo: Topology, joints: JointSet) -> float:
    """Where the neck is narrowest ⊥ its axis (base neck joint → head joint), as a fraction of it."""
    base, head = joints["neck01"], joints["head"]
    fractions = np.linspace(*NECK_SPAN, NECK_SAMPLES)
    normal = unit(head - base)
    girths = [tape_girth(v, topo, base + f * (head - base), normal, base + f * (head - base)).girth
              for f in fractions]
    return soft_least(fractions, np.array(girths), NECK_SOFTNESS)


def _front_neck(v: np.ndarray, faces: np.ndarray, topo: Topology, joints: JointSet) -> SurfacePoint:
    """The jugular notch: the deepest (most backward) point of the front midline profile where
    the throat meets the chest, near the base neck joint's height."""
    base = joints["neck01"]
    sec = section(v, topo, OFF_MIDLINE, np.array([1.0, 0.0, 0.0]))
    low, high = base[1] + FRONT_NECK_SPAN[0], base[1] + FRONT_NECK_SPAN[1]
    p = sec.points[(sec.points[:, 2] > base[2]) & (sec.points[:, 1] > low) & (sec.points[:, 1] < high)]
    p = p[np.argsort(p[:, 1])]
    heights = np.linspace(low, high, FRONT_NECK_SAMPLES)
    y = soft_least(heights, np.interp(heights, p[:, 1], p[:, 2]), FRONT_NECK_SOFTNESS)
    return _ray_point(v, faces, at_height(base, y) + OFF_MIDLINE, FORWARD)


def _side_neck(v: np.ndarray, faces: np.ndarray, topo: Topology, joints: JointSet, neck_level: float,
               acromion: SurfacePoint, search: FaceSearch) -> SurfacePoint:
    """The right side neck point: where the neck's side turns into the shoulder's top. On the
    frontal section through the base neck joint, the point of the shoulder's upper contour
    deepest below the chord from the neck's side (at the neck girth's level) to the acromion."""
    base, head = joints["neck01"], joints["head"]
    neck = base + neck_level * (head - base)
    top = _ray_point(v, faces, neck, -LATERAL).at(v)
    end = acromion.at(v)
    sec = section(v, topo, base, FORWARD)
    p = sec.points[(sec.points[:, 0] < top[0]) & (sec.points[:, 0] > end[0])
                   & (sec.points[:, 1] > end[1]) & (sec.points[:, 1] < top[1])]
    chord = unit(end[:2] - top[:2])
    rel = p[:, :2] - top[:2]
    depth = rel[:, 1] * chord[0] - rel[:, 0] * chord[1]  # below the chord, in the frontal plane
    weights = np.exp((depth - depth.max()) / SIDE_NECK_SOFTNESS)
    return SurfacePoint.nearest(v, faces, weights @ p / weights.sum(), search)


def soft_least(positions: np.ndarray, values: np.ndarray, softness: float) -> float:
    """Where `values` (sampled at `positions`) are least, as the mean position weighted by
    exp(−(value − least) / softness): it moves continuously with the values, where the
    sample of the least value would jump between two near-equal hollows."""
    weights = np.exp(-(values - np.nanmin(values)) / softness)
    weights[~np.isfinite(weights)] = 0.0
    return float(weights @ positions / weights.sum())


def _acromion_offsets(v: np.ndarray, joints: JointSet, right: SurfacePoint,
                      left: SurfacePoint) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    offsets = (right.at(v) - joints[GIRDLE_JOINTS["R"][1]], left.at(v) - joints[GIRDLE_JOINTS["L"][1]])
    return tuple(tuple(float(x) for x in o) for o in offsets)  # type: ignore[return-value]


def girdle_point(marks: Landmarks, rest: JointSet, posed: JointSet, side: str) -> np.ndarray:
    """Where the shoulder girdle carries an acromion ('R' or 'L') in a posture (3,).

    The girdle turns with the thorax (its frame from joint centres, `trunk_frame`) and,
    within it, by the least rotation taking the rest line from the sternoclavicular to the
    glenohumeral joint centre to the posed one; it moves with the glenohumeral centre.
    """
    inner, outer = GIRDLE_JOINTS[side]
    offset = np.asarray(marks.acromion_offsets[0 if side == "R" else 1])
    thorax = trunk_frame(posed, "thorax") @ trunk_frame(rest, "thorax").T
    a, b = thorax @ unit(rest[outer] - rest[inner]), unit(posed[outer] - posed[inner])
    if float(a @ b) < -1.0 + 1e-12:
        raise HitogataError("shoulder girdle turned by 180°: the posture is broken")
    return posed[outer] + shortest_arc(a, b) @ thorax @ offset


def pelvis_point(marks: Landmarks, rest: JointSet, posed: JointSet) -> np.ndarray:
    """Where the pelvis carries the crotch in a posture (3,): its rest offset from the pelvis's origin joint turned
    by the pelvis's frame (`trunk_frame`), as the girdle carries an acromion (`girdle_point`)."""
    turn = trunk_frame(posed, "pelvis") @ trunk_frame(rest, "pelvis").T
    return posed[PELVIS_ORIGIN] + turn @ np.asarray(marks.crotch_offset)


def _thigh_level(v: np.ndarray, crotch: int, joints: JointSet) -> float:
    """Where the thigh girth's plane cuts the femur, as a fraction from hip to knee joint."""
    hip, knee = joints["upperleg01.R"], joints["lowerleg01.R"]
    femur = knee - hip
    below = v[crotch] - THIGH_BELOW_CROTCH * UP - hip
    return float((below @ femur) / (femur @ femur))


@cache
def reference_vertices() -> tuple[int, int, int]:
    """Right and left nipple and the navel, found on MakeHuman's default female shape.

    Nipple: the most forward vertex of each breast (its skin weighted mainly to
    the breast bone). Navel: the front midline vertex that lies deepest behind
    the chord of the profile from NAVEL_REACH above it to NAVEL_REACH below it.
    """
    reference = _reference_body()
    v, rig = reference.vertices, reference.rig
    dominant = reference.skin_weights.toarray().argmax(axis=1)  # dense: 10x the sparse argmax, same columns
    nipples = []
    for side in "RL":
        region = np.flatnonzero(dominant == rig.index(f"breast.{side}"))
        nipples.append(int(region[np.argmax(v[region, 2])]))
    joints = JointSet(rig.names, rig.heads)
    midline = np.flatnonzero(np.abs(v[:, 0]) < MIDLINE_TOLERANCE)
    front = midline[(v[midline, 2] > joints["spine03"][2])]
    front = front[(v[front, 1] > joints["upperleg01.R"][1]) & (v[front, 1] < v[nipples[0], 1])]
    front = front[np.argsort(v[front, 1])]
    y, z = v[front, 1], v[front, 2]
    inner = (y - NAVEL_REACH > y[0]) & (y + NAVEL_REACH < y[-1])
    chord = 0.5 * (np.interp(y - NAVEL_REACH, y, z) + np.interp(y + NAVEL_REACH, y, z))
    navel = front[inner][np.argmax((chord - z)[inner])]
    return nipples[0], nipples[1], int(navel)


def _cervicale(v: np.ndarray, faces: np.ndarray, joints: JointSet) -> SurfacePoint:
    """Back of the neck's base: where a ray from the base neck joint straight backwards leaves the skin."""
    return _ray_point(v, faces, joints["neck01"] + OFF_MIDLINE, -FORWARD)


def _ray_point(v: np.ndarray, faces: np.ndarray, origin: np.ndarray, direction: np.ndarray) -> SurfacePoint:
    face, point = first_hit(v, faces, origin, direction)
    if face < 0:
        where = np.round(origin, 3).tolist()
        raise HitogataError(f"landmark ray from {where} m misses the skin: the body's shape is broken")
    return SurfacePoint.on_face(v, faces[face], point)


def _acromion(v: np.ndarray, faces: np.ndarray, joints: JointSet, side: str) -> SurfacePoint:
    """Shoulder point: skin above the shoulder joint, on a ray tilted slightly outwards."""
    outwards = np.array([1.0 if side == "L" else -1.0, 0.0, 0.0])
    return _ray_point(v, faces, joints[f"upperarm01.{side}"], UP + ACROMION_TILT * outwards)


def _olecranon(v: np.ndarray, faces: np.ndarray, joints: JointSet) -> SurfacePoint:
    """Back of the right elbow: the ray from the elbow joint away from the bend."""
    upper = axis(joints, "upperarm01.R", "lowerarm01.R")
    fore = axis(joints, "lowerarm01.R", "wrist.R")
    back = upper - fore
    return _ray_point(v, faces, joints["lowerarm01.R"], unit(back - (back @ upper) * upper))


def _ulnar_styloid(v: np.ndarray, faces: np.ndarray, joints: JointSet) -> SurfacePoint:
    """Little-finger side of the right wrist: the ray from the wrist joint towards the fifth finger."""
    fore = axis(joints, "lowerarm01.R", "wrist.R")
    ulnar = joints["finger5-1.R"] - joints["finger2-1.R"]
    return _ray_point(v, faces, joints["wrist.R"], unit(ulnar - (ulnar @ fore) * fore))


def _crotch(v: np.ndarray, midline: np.ndarray, joints: JointSet) -> int:
    """Lowest midline point of the trunk, between the legs."""
    low = midline[v[midline, 1] < joints["upperleg01.R"][1]]
    return int(low[np.argmin(v[low, 1])])


def _back_waist(v: np.ndarray, faces: np.ndarray, joints: JointSet, navel: int) -> SurfacePoint:
    """The back at the navel's height: where a ray backwards from the spine there leaves the skin."""
    spine = joints["spine03"]
    return _ray_point(v, faces, np.array([spine[0], v[navel, 1], spine[2]]) + OFF_MIDLINE, -FORWARD)


def iliac_crest_height(joints: JointSet) -> float:
    """The iliac crest's height (m, the rest frame's y): `LEVEL_ILIAC_CREST` of the way from the hip
    joints' centre up to the base neck joint (C7/T1)."""
    hips = 0.5 * (joints["upperleg01.R"][1] + joints["upperleg01.L"][1])
    return float(hips + LEVEL_ILIAC_CREST * (joints["neck01"][1] - hips))


def _iliac_crest(v: np.ndarray, faces: np.ndarray, joints: JointSet, armpits: dict[str, Any]) -> SurfacePoint:
    """The right iliocristale: at the iliac crest's height (`iliac_crest_height`), where a ray from the
    midline sideways along the midaxillary line (midway between the right armpit's front and back folds,
    in depth) meets the flank: ANSUR II's iliocristale and NHANES's waist are taken there."""
    folds = (armpits["fold_front_right"].at(v)[2] + armpits["fold_back_right"].at(v)[2]) / 2.0
    origin = np.array([joints["spine04"][0], iliac_crest_height(joints), folds])
    return _ray_point(v, faces, origin, -LATERAL)


def _inframammary_fold(v: np.ndarray, faces: np.ndarray, bust: int, waist_y: float) -> int:
    """Under the right breast: on the front profile through the bust point, the deepest
    point below the chord from the bust point to the waist level (the fold's corner)."""
    sec = section(v, topology(faces), v[bust], np.array([1.0, 0.0, 0.0]))
    p = sec.points
    front = p[(p[:, 1] < v[bust, 1]) & (p[:, 1] > waist_y) & (p[:, 2] > v[bust, 2] - CHEST_FRONT)]
    end = front[np.argmin(front[:, 1])]
    chord = unit(end[1:] - v[bust, 1:])
    rel = front[:, 1:] - v[bust, 1:]
    depth = rel[:, 1] * chord[0] - rel[:, 0] * chord[1]  # distance behind the chord, (y, z) plane
    fold = front[np.argmax(depth)]
    return int(np.argmin(np.linalg.norm(v - fold, axis=1)))


def _buttock(v: np.ndarray, crotch_y: float, waist_y: float) -> int:
    """Most backward point of the right buttock between crotch and waist levels."""
    region = np.flatnonzero((v[:, 0] < 0.0) & (v[:, 1] > crotch_y) & (v[:, 1] < waist_y))
    return int(region[np.argmin(v[region, 2])])
