"""The armpit landmarks of ISO 8559-1: the axilla level and the front and back armpit fold points.

ISO 8559-1 takes the across-back width between the posterior armpit fold
points and the across-front width between the anterior ones, where the
armscye meets the level of a ruler held up in the armpit (the axilla); the
armscye girth passes over the acromion and both fold points and under the
arm. On the rest surface (the A-pose holds the arms clear of the trunk below
the axilla):

- the axilla level: going down from the shoulder joint, the highest
  horizontal section in which the arm's loop (round the humerus) is apart
  from the trunk's (round the spine): a 1 cm scan, then bisection to
  BISECTION_STEPS, so the level varies continuously with the shape; the
  higher of the two sides;
- the fold points: FOLD_ABOVE over it, where arm and trunk are one loop, going
  along the section from the midline outwards, behind the humerus's axis (back)
  and in front of it (front), where the skin starts to follow the arm by
  FOLD_WEIGHT (its skinning weight on the upper-arm bones, interpolated between
  section points): where the trunk ends and the arm begins. Mostly the
  trunk's skin, the point does not swing round with the arm in a posture;
Each point is an exact point of the skin (`SurfacePoint`), so it moves
continuously with the shape. The skin weights are MakeHuman's, the same for
every body.
"""

from __future__ import annotations

from functools import cache

import numpy as np

from hitogata.body.assets import load_assets
from hitogata.errors import HitogataError
from hitogata.measure.axes import UP, JointSet
from hitogata.measure.sections import loops_around, section
from hitogata.measure.surface_points import FaceSearch, SurfacePoint
from hitogata.geometry.topology import Topology

SCAN_STEP = 0.01  # m between the sections scanned for the axilla
SCAN_DEPTH = 0.25  # m below the shoulder joint
BISECTION_STEPS = 6  # halvings of SCAN_STEP: the axilla level to 0.16 mm
FOLD_ABOVE = 0.01  # m: the fold points lie this far above the axilla level
FOLD_WEIGHT = 0.3  # the fold: where the skin starts to follow the arm (its weight on the upper-arm bones)


@cache
def upper_arm_weights() -> dict[str, np.ndarray]:
    """Per side ('R', 'L'), each skin vertex's weight (V,) on the upper-arm bones."""
    assets = load_assets()
    columns = {side: [assets.bone_names.index(f"upperarm0{k}.{side}") for k in (1, 2)] for side in "RL"}
    return {side: np.asarray(assets.skin_weights[:, cols].sum(axis=1)).ravel() for side, cols in columns.items()}


def armpit_points(v: np.ndarray, faces: np.ndarray, topo: Topology, joints: JointSet,
                  search: FaceSearch) -> dict[str, object]:
    """The axilla height (m, at rest) and the four fold points (fold_back_right, …) of a rest
    surface (`search`: its `FaceSearch`)."""
    axilla = max(_axilla(v, topo, joints, side) for side in "RL")
    level = axilla + FOLD_ABOVE
    sec = section(v, topo, np.array([0.0, level, 0.0]), UP)
    centre = at_height(joints["spine02"], level)
    kept = np.isin(sec.loop, loops_around(sec, centre, UP))
    points, edges = sec.points[kept], topo.edges[sec.edges[kept]]
    along = np.linalg.norm(points - v[edges[:, 0]], axis=1) / np.linalg.norm(v[edges[:, 1]] - v[edges[:, 0]], axis=1)
    weights = upper_arm_weights()
    found: dict[str, object] = {"axilla": float(axilla)}
    for side, sign in (("right", -1.0), ("left", 1.0)):
        arm = weights[side[0].upper()]
        on_arm = arm[edges[:, 0]] * (1.0 - along) + arm[edges[:, 1]] * along
        arm_z = _arm_point(joints, side[0].upper(), level)[2]
        for face, z_sign in (("back", -1.0), ("front", 1.0)):
            mine = np.flatnonzero((np.sign(points[:, 0]) == sign) & (np.sign(points[:, 2] - arm_z) == z_sign))
            mine = mine[np.argsort(np.abs(points[mine, 0]))]  # from the midline outwards
            reached = np.flatnonzero(on_arm[mine] >= FOLD_WEIGHT)
            if not len(reached) or reached[0] == 0:
                raise HitogataError(f"armpit {face} fold ({side}): no trunk-to-arm skin at {level:.3f} m; "
                                    "the body's shape is outside what the rule handles")
            a, b = mine[reached[0] - 1], mine[reached[0]]
            t = (FOLD_WEIGHT - on_arm[a]) / (on_arm[b] - on_arm[a])
            fold = points[a] + t * (points[b] - points[a])
            found[f"fold_{face}_{side}"] = SurfacePoint.nearest(v, faces, fold, search)
    return found


def at_height(point: np.ndarray, y: float) -> np.ndarray:
    """The point moved vertically to the height y."""
    out = np.array(point, dtype=np.float64)
    out[1] = y
    return out


def _apart(v: np.ndarray, topo: Topology, joints: JointSet, side: str, y: float) -> bool:
    """Whether at height y the arm's section loop is apart from the trunk's."""
    sec = section(v, topo, np.array([0.0, y, 0.0]), UP)
    around_arm = set(loops_around(sec, _arm_point(joints, side, y), UP))
    around_trunk = set(loops_around(sec, at_height(joints["spine02"], y), UP))
    return bool(around_arm and around_trunk and not around_arm & around_trunk)


def _axilla(v: np.ndarray, topo: Topology, joints: JointSet, side: str) -> float:
    """The highest level below the shoulder joint at which the arm's section is apart from the trunk's."""
    shoulder = joints[f"upperarm01.{side}"][1]
    for y in np.arange(shoulder - SCAN_STEP, shoulder - SCAN_DEPTH, -SCAN_STEP):
        if _apart(v, topo, joints, side, y):
            low, high = float(y), float(y) + SCAN_STEP
            for _ in range(BISECTION_STEPS):
                middle = 0.5 * (low + high)
                low, high = (middle, high) if _apart(v, topo, joints, side, middle) else (low, middle)
            return low
    raise HitogataError(f"axilla ({side}): the arm joins the trunk down to {SCAN_DEPTH * 100:.0f} cm below "
                        "the shoulder; allowed a body whose arms hang clear of the trunk at rest")


def _arm_point(joints: JointSet, side: str, y: float) -> np.ndarray:
    """Where the humerus (shoulder → elbow joint) crosses the level y (extended above the shoulder)."""
    shoulder, elbow = joints[f"upperarm01.{side}"], joints[f"lowerarm01.{side}"]
    return at_height(shoulder + (y - shoulder[1]) / (elbow[1] - shoulder[1]) * (elbow - shoulder), y)
