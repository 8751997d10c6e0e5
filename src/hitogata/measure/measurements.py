"""The main ISO 8559-1 body measurements, on a body in any posture.

Input: the body (its topology, rest surface and rest joints define the
landmarks) and, for a posed or deformed body, its vertex array and the rig's
joint centres in that posture. Girths are tape girths of planar sections
(`sections.tape_girth`), lengths are exact surface geodesics
(`geodesic.SurfaceGeodesics`). Each definition is in docs/measurements.md.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from hitogata.body.model import Body
from hitogata.errors import HitogataError, excerpt
from hitogata.measure.armpits import FOLD_ABOVE
from hitogata.measure.axes import JointSet, axis, trunk_frame, trunk_normal, unit
from hitogata.measure.geodesic import SurfaceGeodesics, polyline_length
from hitogata.measure.landmarks import Landmarks, body_landmarks, girdle_point, pelvis_point
from hitogata.measure.sections import Tape, arc_tape, loops_around, section, split_tape, tape_girth
from hitogata.measure.surface_points import SurfacePoint, face_of, insert_points
from hitogata.geometry.topology import Topology, topology
from hitogata.posing.body_split import mainly_weighted
from hitogata.measure.values import GIRTHS, MEASUREMENT_NAMES, Measurements, check_names, undefined_because

__all__ = ["GIRTHS", "MEASUREMENT_NAMES", "Measurements", "check_names", "measure", "measure_surface",
           "measure_with_paths", "measurement_paths", "undefined_because"]

if TYPE_CHECKING:
    from hitogata.posing.pose import PosedBody


def measure(
    body: Body | PosedBody, vertices: np.ndarray | None = None, joints: np.ndarray | None = None
) -> Measurements:
    """All measurements of `body` at rest, of a `PosedBody` in its posture, or of `body` in the
    posture given by `vertices` and `joints`.

    `vertices` (V, 3) share the body's topology; `joints` (B, 3) are the rig's joint
    centres (heads, in `body.rig.names` order) in the same posture. Both default to rest.
    """
    body, vertices, joints = posture_of(body, vertices, joints)
    vertices, posed = posture_arrays(body, vertices, joints)
    rest = JointSet(body.rig.names, body.rig.heads)
    return measure_surface(vertices, body.faces, body_landmarks(body), rest, posed, tape_skin(body))


def posture_of(
    body: Body | PosedBody, vertices: np.ndarray | None, joints: np.ndarray | None
) -> tuple[Body, np.ndarray | None, np.ndarray | None]:
    """The body and its posture's arrays, from a `Body` with optional arrays or from a `PosedBody`."""
    if isinstance(body, Body):
        return body, vertices, joints
    if not hasattr(body, "body") or not isinstance(body.body, Body):
        raise HitogataError(f"body {excerpt(type(body).__name__)}: allowed a Body or a PosedBody "
                            "(e.g. Body.from_measurements(sex='female'))")
    if vertices is not None or joints is not None:
        raise HitogataError("a posed body carries its vertices and joints: give the PosedBody alone")
    return body.body, body.vertices, body.rig_joints


def posture_arrays(body: Body, vertices: np.ndarray | None, joints: np.ndarray | None) -> tuple[np.ndarray, JointSet]:
    """Checked (V, 3) vertices and joint centres of a posture (rest where not given)."""
    vertices = checked_points("vertices", body.vertices if vertices is None else vertices, len(body.vertices))
    heads = checked_points("joints", body.rig.heads if joints is None else joints, len(body.rig.names))
    return vertices, JointSet(body.rig.names, heads)


def checked_points(label: str, array: object, count: int) -> np.ndarray:
    """A finite float (count, 3) array, or a one-line error saying what was wrong."""
    array = np.asarray(array, dtype=np.float64)
    if array.shape != (count, 3):
        raise HitogataError(f"{label}: shape {array.shape}, allowed ({count}, 3)")
    if not np.isfinite(array).all():
        bad = int(np.flatnonzero(~np.isfinite(array).all(axis=1))[0])
        raise HitogataError(f"{label}: row {bad} is not finite ({array[bad].tolist()}); allowed finite metres")
    return array


Plane = tuple[np.ndarray, np.ndarray, np.ndarray]  # a point on the plane, its normal, a point inside the part

# The skin each tape may rest on (vertices mainly weighted to the listed bones, matched by name
# prefix: `hitogata.posing.body_split.mainly_weighted`): the limb's own skin for a limb girth,
# all but the limbs' for a trunk girth. At rest this changes nothing (tested on bodies across
# the supported range); where a posture joins the part's section to its neighbour's through
# the mesh (a thigh raised to the belly: one loop through the groin) the tape still goes
# round the part, not round both.
ARM_BONES = ("upperarm", "lowerarm", "wrist", "metacarpal", "finger")
LEG_BONES = ("upperleg02", "lowerleg", "foot", "toe")
TAPE_SKIN: dict[str, tuple[str, tuple[str, ...]]] = {
    **{name: ("not", ARM_BONES + LEG_BONES)
       for name in ("chest_girth", "underbust_girth", "waist_girth", "omphalion_waist_girth", "iliac_crest_waist_girth",
                    "hip_girth")},
    "thigh_girth": ("only", ("upperleg01.R", "upperleg02.R", "pelvis.R", "spine05")),  # + the groin's skin
    "upper_arm_girth": ("only", ("upperarm01.R", "upperarm02.R")),
    "knee_girth": ("only", ("upperleg02.R", "lowerleg01.R")),
    "calf_girth": ("only", ("lowerleg01.R", "lowerleg02.R")),
    "ankle_girth": ("only", ("lowerleg02.R", "foot.R")),
    "wrist_girth": ("only", ("lowerarm02.R", "wrist.R")),
}

def tape_skin(body: Body) -> dict[str, np.ndarray]:
    """Per girth, the (V,) mask of skin its tape may rest on (TAPE_SKIN), found once per body and kept with it."""
    return body.prepared(find_tape_skin)


def find_tape_skin(body: Body) -> dict[str, np.ndarray]:
    """Per girth, the (V,) mask of skin its tape may rest on (TAPE_SKIN)."""
    found = {}
    for name, (mode, prefixes) in TAPE_SKIN.items():
        main = mainly_weighted(body, [i for i, bone in enumerate(body.rig.names) if bone.startswith(prefixes)])
        found[name] = main if mode == "only" else ~main
    return found


def girth_planes(vertices: np.ndarray, marks: Landmarks, rest: JointSet, posed: JointSet) -> dict[str, Plane]:
    """Where each planar girth but the armscye's is taken in this posture (docs/measurements.md)."""
    v = vertices
    hip_joint, knee = posed["upperleg01.R"], posed["lowerleg01.R"]
    thigh_point = hip_joint + marks.thigh_level * (knee - hip_joint)
    ankle = posed["foot.R"]
    calf, narrow = knee + marks.calf_level * (ankle - knee), knee + marks.ankle_level * (ankle - knee)
    wrist, styloid = posed["wrist.R"], marks.ulnar_styloid.at(v)
    forearm = unit(wrist - posed["lowerarm01.R"])
    shoulder, elbow = posed["upperarm01.R"], posed["lowerarm01.R"]
    humerus = unit(elbow - shoulder)
    middle = 0.5 * (girdle_point(marks, rest, posed, "R") + marks.olecranon.at(v))
    arm_point = shoulder + ((middle - shoulder) @ humerus) * humerus
    thorax, waist = trunk_normal(rest, posed, "thorax"), trunk_normal(rest, posed, "waist")
    neck = posed["neck01"] + marks.neck_level * (posed["head"] - posed["neck01"])
    return {
        "neck_girth": (neck, axis(posed, "neck01", "head"), neck),
        "chest_girth": (0.5 * (v[marks.bust_right] + v[marks.bust_left]), thorax, posed["spine01"]),
        "underbust_girth": (v[marks.underbust], thorax, posed["spine01"]),
        "waist_girth": (0.5 * (marks.waist_front.at(v) + marks.waist_back.at(v)), waist, posed["spine03"]),
        "omphalion_waist_girth": (0.5 * (v[marks.omphalion] + marks.omphalion_back.at(v)), waist, posed["spine03"]),
        "iliac_crest_waist_girth": (marks.iliac_crest.at(v), trunk_normal(rest, posed, "pelvis"), posed["spine04"]),
        "hip_girth": (v[marks.buttock], trunk_normal(rest, posed, "pelvis"), posed["spine05"]),
        "thigh_girth": (thigh_point, unit(knee - hip_joint), thigh_point),
        "upper_arm_girth": (arm_point, humerus, arm_point),
        "knee_girth": (knee, unit(unit(knee - hip_joint) + unit(ankle - knee)), knee),
        "calf_girth": (calf, unit(ankle - knee), calf),
        "ankle_girth": (narrow, unit(ankle - knee), narrow),
        "wrist_girth": (styloid, forearm, wrist),
    }


# The farthest the knee girth's plane may cut the leg along femur or tibia, in knee widths (`knee_along_limbs`):
# between the default bodies' sitting (hips and knees 90°: at most 0.74, skinned and elastic) and 110° of knee
# flexion (0.88-1.08), so a seated knee keeps its girth and past about 105° no surface gives one
KNEE_REACH = 0.85


def knee_along_limbs(vertices: np.ndarray, topo: Topology, plane: Plane, posed: JointSet,
                     part: np.ndarray | None) -> bool:
    """Whether the knee girth's plane runs along the thigh and the calf (`values.KNEE_ALONG_LIMBS`): the leg's
    skin it cuts near the knee (`part`; every loop of it within one knee width of the knee's centre) reaches
    along the femur or the tibia further from the knee than `KNEE_REACH` knee widths (the knee's own section's
    extent along the flexion axis). The plane bisects femur and tibia, so it cuts a limb of width w, flexed
    by θ, over about w/2 · tan(θ/2) along it: on the default bodies (skinned and elastic alike) 8-9 cm sitting
    at 90°, 13 cm at 110°, 18-20 cm in a deep squat (130°) or kneeling (135°), against a knee 11-15 cm wide
    (the elastic knee's sides swell beside the thigh-calf contact). Beyond, the section takes in the back of
    the thigh and the calf, joined to the knee's or beside it (a tape round it, 40-62 cm, measures no knee);
    a straight knee's plane is square to the leg."""
    origin, normal, centre = plane
    knee = posed["lowerleg01.R"]
    up, down = unit(posed["upperleg01.R"] - knee), unit(posed["foot.R"] - knee)
    flexion_axis = np.cross(up, down)
    if np.linalg.norm(flexion_axis) < 1e-6:
        return False
    n = unit(normal)
    centre = centre - ((centre - origin) @ n) * n
    sec = section(vertices, topo, origin, n)
    ends = topo.edges[sec.edges]
    leg = np.ones(len(ends), dtype=bool) if part is None else part[ends[:, 0]] | part[ends[:, 1]]
    own = leg & np.isin(sec.loop, loops_around(sec, centre, n))
    if not own.any():
        return False
    width = float(np.ptp(sec.points[own] @ unit(flexion_axis)))
    near = leg & np.isin(sec.loop, sec.loop[leg & (np.linalg.norm(sec.points - centre, axis=1) < width)])
    along = np.maximum((sec.points[near] - knee) @ up, (sec.points[near] - knee) @ down)
    return bool(along.max() > KNEE_REACH * width)


def tapes(
    vertices: np.ndarray,
    faces: np.ndarray,
    marks: Landmarks,
    rest: JointSet,
    posed: JointSet,
    skin: dict[str, np.ndarray] | None = None,
) -> dict[str, Tape]:
    """The girths, the across widths and the crotch length with its front and back rise, with the paths their
    tapes follow; `skin` as from `tape_skin`."""
    topo, skin = topology(faces), skin or {}
    planes = girth_planes(vertices, marks, rest, posed)
    girths = {name: tape_girth(vertices, topo, *plane, part=skin.get(name)) for name, plane in planes.items()}
    if knee_along_limbs(vertices, topo, planes["knee_girth"], posed, skin.get("knee_girth")):
        girths["knee_girth"] = Tape(girth=float("nan"), path=np.empty((0, 3)))
    girths["armscye_girth"] = armscye_tape(vertices, topo, marks, rest, posed)
    thorax, trunk = trunk_normal(rest, posed, "thorax"), skin.get("chest_girth")
    widths = {name: arc_tape(vertices, topo, (left.at(vertices), middle.at(vertices), right.at(vertices)),
                             posed["spine02"], thorax, trunk)
              for name, (left, middle, right) in width_points(marks).items()}
    return {**girths, **widths, **crotch_tapes(vertices, topo, marks, rest, posed)}


def crotch_tapes(vertices: np.ndarray, topo: Topology, marks: Landmarks, rest: JointSet,
                 posed: JointSet) -> dict[str, Tape]:
    """The crotch length and its two parts, the front rise (waist front → crotch) and the back rise (crotch →
    waist back): one tape in the pelvis's midsagittal plane through the crotch (the waist's front and back points
    projected onto it), round the section below the waist's chord, hollows bridged (`sections.arc_tape`), cut
    where it passes the crotch (`sections.split_tape`). The crotch is where the pelvis carries it
    (`landmarks.pelvis_point`): the skin's crotch vertex slides with the thighs (skinning) or is drawn up between
    them (the elastic skin). The plane turns with the pelvis, not with the waist: in a trunk twist the plane of
    the three points cut the seat obliquely (+6 to +8 cm), where a tape follows the pelvis's midline."""
    crotch = pelvis_point(marks, rest, posed)
    tape = arc_tape(vertices, topo, (marks.waist_front.at(vertices), crotch, marks.waist_back.at(vertices)),
                    posed["spine04"], normal=trunk_frame(posed, "pelvis")[:, 0], bounded=False)
    front, back = split_tape(tape, crotch)
    return {"crotch_length": tape, "front_rise": front, "back_rise": back}


def armscye_tape(vertices: np.ndarray, topo: Topology, marks: Landmarks, rest: JointSet, posed: JointSet) -> Tape:
    """The right armscye girth: in the plane through the acromion (carried by the girdle) and
    the front and back armpit fold points, round the shoulder joint, passing under the arm
    at the axilla (FOLD_ABOVE below the line through the fold points); the hull, as a tape."""
    acromion = girdle_point(marks, rest, posed, "R")
    front, back = marks.fold_front_right.at(vertices), marks.fold_back_right.at(vertices)
    normal = unit(np.cross(front - acromion, back - acromion))
    return tape_girth(vertices, topo, acromion, normal, posed["upperarm01.R"],
                      above=(back, unit(_across(acromion - back, unit(front - back))), -FOLD_ABOVE))


def _across(vector: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """The part of `vector` perpendicular to the unit `direction`."""
    return vector - (vector @ direction) * direction


# Each surface length's route through landmarks (`Landmarks` fields), in order.
SURFACE_ROUTES = {
    "back_waist_length": ("cervicale", "omphalion_back"),
    "shoulder_width": ("acromion_left", "cervicale", "acromion_right"),
    "shoulder_length": ("side_neck", "acromion_right"),
    "arm_length": ("acromion_right", "olecranon", "ulnar_styloid"),
    "waist_to_hip_length": ("waist_side", "hip_side"),
}
SURFACE_ENDS = ("olecranon", "ulnar_styloid", "cervicale", "omphalion_back", "side_neck", "waist_side",
                "hip_side")  # the points between vertices (the acromia: the girdle's)


def width_points(marks: Landmarks) -> dict[str, tuple[SurfacePoint, SurfacePoint, SurfacePoint]]:
    """The across widths' ends and middle: a tape laid from armpit fold to armpit fold over the
    midline point at their level, in the thorax's horizontal (`sections.arc_tape`; the crotch
    length is such a tape too, `crotch_tapes`)."""
    return {"across_back_width": (marks.fold_back_left, marks.back_middle, marks.fold_back_right),
            "across_front_width": (marks.fold_front_left, marks.front_middle, marks.fold_front_right)}


def surface_paths(vertices: np.ndarray, faces: np.ndarray, marks: Landmarks, rest: JointSet,
                  posed: JointSet) -> dict[str, np.ndarray]:
    """The geodesic polylines of the surface lengths (`SURFACE_ROUTES`).

    The acromions are where the shoulder girdle carries them (`girdle_point`), on the skin
    nearest there; the other points ride the skin. Each becomes a vertex of the surface the
    paths run on (`insert_points`).
    """
    ends = {"acromion_right": girdle_point(marks, rest, posed, "R"),
            "acromion_left": girdle_point(marks, rest, posed, "L")}
    ends.update({name: getattr(marks, name).at(vertices) for name in SURFACE_ENDS})
    hints = [-1, -1] + [face_of(faces, getattr(marks, name)) for name in SURFACE_ENDS]
    v, f, indices = insert_points(vertices, faces, np.stack(list(ends.values())), np.array(hints))
    at = dict(zip(ends, indices.tolist()))
    paths = SurfaceGeodesics(v, f)
    return {name: paths.path_through(*(at[point] for point in route)) for name, route in SURFACE_ROUTES.items()}


def heights(vertices: np.ndarray, marks: Landmarks) -> dict[str, float]:
    """Stature, the iliac crest's height and crotch height: vertical distances above the lowest skin
    point (the floor)."""
    floor = float(vertices[:, 1].min())
    return {
        "stature": float(vertices[marks.head_top, 1]) - floor,
        "iliocristale_height": float(marks.iliac_crest.at(vertices)[1]) - floor,
        "inside_leg": float(vertices[marks.crotch, 1]) - floor,
    }


def measure_surface(
    vertices: np.ndarray,
    faces: np.ndarray,
    marks: Landmarks,
    rest: JointSet,
    posed: JointSet,
    skin: dict[str, np.ndarray] | None = None,
) -> Measurements:
    """The measurements of any surface with landmark vertices `marks` (e.g. a subdivided body);
    `skin`: per girth, the vertices its tape may rest on (`tape_skin`; None: any skin)."""
    return _measured(vertices, faces, marks, rest, posed, skin)[0]


def _measured(vertices: np.ndarray, faces: np.ndarray, marks: Landmarks, rest: JointSet, posed: JointSet,
              skin: dict[str, np.ndarray] | None) -> tuple[Measurements, dict[str, np.ndarray]]:
    """The measurements and where each tape lies (`measure_surface`, `measurement_paths`): one search."""
    values = heights(vertices, marks)
    lengths = surface_paths(vertices, faces, marks, rest, posed)
    found = tapes(vertices, faces, marks, rest, posed, skin)
    values.update({name: polyline_length(path) for name, path in lengths.items()})
    values.update({name: tape.girth for name, tape in found.items()})
    loops = {name: np.vstack([t.path, t.path[:1]]) if name in GIRTHS else t.path
             for name, t in found.items() if len(t.path)}
    return Measurements(**values), {**loops, **lengths}


def measurement_paths(
    body: Body | PosedBody, vertices: np.ndarray | None = None, joints: np.ndarray | None = None
) -> dict[str, np.ndarray]:
    """Where each tape lies, for pictures: closed hull loops of the girths, open polylines of the
    across widths and the surface lengths."""
    return measure_with_paths(body, vertices, joints)[1]


def measure_with_paths(
    body: Body | PosedBody, vertices: np.ndarray | None = None, joints: np.ndarray | None = None
) -> tuple[Measurements, dict[str, np.ndarray]]:
    """`measure` and `measurement_paths` at once (the tapes are laid once for both)."""
    body, vertices, joints = posture_of(body, vertices, joints)
    vertices, posed = posture_arrays(body, vertices, joints)
    rest = JointSet(body.rig.names, body.rig.heads)
    return _measured(vertices, body.faces, body_landmarks(body), rest, posed, tape_skin(body))
