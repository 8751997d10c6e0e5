"""Across-back and across-front widths: the surface distance between the armpit fold points.

ISO 8559-1 takes the back width between the armpit back fold points, where
the armscye line crosses the level of a ruler held up in the armpit (the
axilla), and the front width likewise between the front fold points. On the
rest surface (the A-pose holds the arms clear of the trunk below the axilla):

- the axilla level: scanning down from the shoulder joint, the first
  horizontal section in which the arm's loop (round the humerus) no longer
  joins the trunk's (round the spine); the higher of the two sides;
- the fold points: FOLD_ABOVE over it, where arm and trunk are one loop,
  going along the section from the midline outwards, behind the humerus's
  axis (back) and in front of it (front), the first point whose skin follows
  the arm by FOLD_WEIGHT (its skinning weight on the upper-arm bones): where
  the trunk ends and the arm begins. The nearest skin vertex is kept (a
  landmark that follows the skin into any posture, as the others in
  `measure`); being mostly the trunk's, it does not swing round with the arm.

The widths are geodesics over the back and over the front between the fold
vertices of the two sides through the midline vertex at that level, as a
tape laid across the back (or the chest) takes them.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np

from hitogata.body import Body
from hitogata.errors import HitogataError
from hitogata.measure.axes import UP, JointSet
from hitogata.measure.geodesic import SurfaceGeodesics, polyline_length
from hitogata.measure.sections import loops_around, section
from hitogata.measure.topology import topology

SCAN_STEP = 0.002  # m between the sections scanned for the axilla
SCAN_DEPTH = 0.25  # m below the shoulder joint
FOLD_ABOVE = 0.01  # m: the fold points lie this far above the axilla level
FOLD_WEIGHT = 0.3  # the fold: where the skin starts to follow the arm (its weight on the upper-arm bones)
MIDLINE_TOLERANCE = 1e-3  # m: vertices this close to x = 0 lie on the midline
WIDTHS = ("across_back_width", "across_front_width")


@dataclass(frozen=True)
class ArmpitFolds:
    """Vertex indices of the four armpit fold points and the axilla height at rest (m)."""

    back_right: int
    back_left: int
    front_right: int
    front_left: int
    back_middle: int  # the back's midline at the folds' level: the tape stays on the back
    front_middle: int
    axilla: float


_BY_BODY: weakref.WeakKeyDictionary[Body, ArmpitFolds] = weakref.WeakKeyDictionary()


def armpit_folds(body: Body) -> ArmpitFolds:
    """The fold points of a body, found once on its rest surface and cached."""
    found = _BY_BODY.get(body)
    if found is None:
        weights = {side: np.asarray(body.skin_weights[:, [body.rig.index(f"upperarm0{k}.{side}") for k in (1, 2)]]
                                    .sum(axis=1)).ravel() for side in "RL"}
        found = find_folds(body.vertices, body.faces, JointSet(body.rig.names, body.rig.heads), weights)
        _BY_BODY[body] = found
    return found


def find_folds(vertices: np.ndarray, faces: np.ndarray, joints: JointSet, weights) -> ArmpitFolds:
    """Apply the rules above to a rest surface, its rig joint centres and its skin weights on the
    upper-arm bones of each side ({'R': (V,), 'L': (V,)})."""
    topo = topology(faces)
    axilla = max(_axilla(vertices, topo, joints, side) for side in "RL")
    level = axilla + FOLD_ABOVE
    sec = section(vertices, topo, np.array([0.0, level, 0.0]), UP)
    centre = joints["spine02"].copy()
    centre[1] = level
    kept = np.isin(sec.loop, loops_around(sec, centre, UP))
    points, edges = sec.points[kept], topo.edges[sec.edges[kept]]
    along = np.linalg.norm(points - vertices[edges[:, 0]], axis=1) / np.linalg.norm(
        vertices[edges[:, 1]] - vertices[edges[:, 0]], axis=1)
    out = {}
    for side, sign in (("right", -1.0), ("left", 1.0)):
        arm = weights[side[0].upper()]
        on_arm = arm[edges[:, 0]] * (1 - along) + arm[edges[:, 1]] * along
        arm_z = _arm_point(joints, side[0].upper(), level)[2]
        for face, z_sign in (("back", -1.0), ("front", 1.0)):
            mine = np.flatnonzero((np.sign(points[:, 0]) == sign) & (np.sign(points[:, 2] - arm_z) == z_sign))
            mine = mine[np.argsort(np.abs(points[mine, 0]))]  # from the midline outwards
            reached = mine[on_arm[mine] >= FOLD_WEIGHT]
            if not len(reached):
                raise HitogataError(f"armpit {face} fold ({side}): no skin of the arm at {level:.3f} m; "
                                    "the body's shape is outside what the rule handles")
            out[f"{face}_{side}"] = int(np.argmin(np.linalg.norm(vertices - points[reached[0]], axis=1)))
    out["back_middle"] = _midline(vertices, level, centre[2], -1.0)
    out["front_middle"] = _midline(vertices, level, centre[2], 1.0)
    return ArmpitFolds(**out, axilla=float(axilla))


def _midline(vertices: np.ndarray, level: float, centre_z: float, z_sign: float) -> int:
    """The midline vertex nearest the level, behind (−1) or in front of (+1) the spine's joint."""
    midline = np.flatnonzero((np.abs(vertices[:, 0]) < MIDLINE_TOLERANCE)
                             & (np.sign(vertices[:, 2] - centre_z) == z_sign))
    return int(midline[np.argmin(np.abs(vertices[midline, 1] - level))])


def _axilla(vertices: np.ndarray, topo, joints: JointSet, side: str) -> float:
    """The highest level below the shoulder joint at which the arm's section is apart from the trunk's."""
    shoulder = joints[f"upperarm01.{side}"]
    for y in np.arange(shoulder[1] - SCAN_STEP, shoulder[1] - SCAN_DEPTH, -SCAN_STEP):
        sec = section(vertices, topo, np.array([0.0, y, 0.0]), UP)
        arm = _arm_point(joints, side, y)
        trunk = joints["spine02"].copy()
        trunk[1] = y
        around_arm, around_trunk = set(loops_around(sec, arm, UP)), set(loops_around(sec, trunk, UP))
        if around_arm and around_trunk and not around_arm & around_trunk:
            return float(y)
    raise HitogataError(f"axilla ({side}): the arm joins the trunk down to {SCAN_DEPTH * 100:.0f} cm below "
                        "the shoulder; allowed a body whose arms hang clear of the trunk at rest")


def _arm_point(joints: JointSet, side: str, y: float) -> np.ndarray:
    """Where the humerus (shoulder → elbow joint) crosses the level y (extended above the shoulder)."""
    shoulder, elbow = joints[f"upperarm01.{side}"], joints[f"lowerarm01.{side}"]
    point = shoulder + (y - shoulder[1]) / (elbow[1] - shoulder[1]) * (elbow - shoulder)
    point[1] = y
    return point


def across_widths(body: Body, vertices: np.ndarray | None = None,
                  geodesics: SurfaceGeodesics | None = None) -> dict[str, float]:
    """Across-back and across-front widths (m) of the body at rest or in a posture (V, 3)."""
    folds = armpit_folds(body)
    paths = geodesics or SurfaceGeodesics(body.vertices if vertices is None else vertices, body.faces)
    return {"across_back_width": polyline_length(paths.path_through(folds.back_left, folds.back_middle,
                                                                    folds.back_right)),
            "across_front_width": polyline_length(paths.path_through(folds.front_left, folds.front_middle,
                                                                     folds.front_right))}
