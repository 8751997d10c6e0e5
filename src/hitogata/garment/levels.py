"""Where a garment's girths lie on the body: the leg levels of compression hosiery and the trunk's.

RAL-GZ 387-1 measures a stocking's pressure at named levels of the leg:
B (the ankle: the least girth above the malleoli), C (the calf: its greatest
girth), D (below the knee), E (the knee), G (the top of the thigh). Here:

- ankle: the least girth of the lower leg, ⊥ the shank (knee → ankle joint),
  between ANKLE_RANGE of the way down; calf: the greatest, within CALF_RANGE.
  Both are found once on the rest body (fractions along the shank, cached)
  and follow the shank in any posture, as the thigh level follows the femur;
- knee: through the knee joint, ⊥ the bisector of thigh and shank (in a bent
  knee the plane stays between the two bones);
- thigh, hip, waist: the ISO 8559-1 girths of `hitogata.measure`.

Right side, as the measurements.
"""

from __future__ import annotations

import weakref

import numpy as np

from hitogata.body import Body
from hitogata.measure.axes import JointSet, unit
from hitogata.measure.landmarks import body_landmarks
from hitogata.measure.measurements import MAIN_WEIGHT, girth_planes, tape_skin
from hitogata.measure.sections import Tape, tape_girth
from hitogata.measure.topology import topology

LEVELS = ("ankle", "calf", "knee", "thigh", "hip", "waist")
ANKLE_RANGE = (0.55, 0.92)  # fractions of knee → ankle joint
CALF_RANGE = (0.10, 0.60)
SCAN = 40  # sections per range
SHANK_SKIN = ("lowerleg01.R", "lowerleg02.R", "foot.R")
KNEE_SKIN = ("upperleg02.R", "lowerleg01.R")

Plane = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None]  # origin, normal, centre, skin mask

_SHANK: weakref.WeakKeyDictionary[Body, tuple[float, float]] = weakref.WeakKeyDictionary()


def level_planes(body: Body, vertices: np.ndarray, posed: JointSet) -> dict[str, Plane]:
    """The six levels' planes in a posture (vertices (V, 3), posed rig joint centres)."""
    marks, rest = body_landmarks(body), JointSet(body.rig.names, body.rig.heads)
    skins = _skins(body)
    knee, ankle, hip = posed["lowerleg01.R"], posed["foot.R"], posed["upperleg01.R"]
    shank = unit(ankle - knee)
    ankle_at, calf_at = shank_levels(body)
    trunk = girth_planes(vertices, marks, rest, posed)
    planes = {
        "ankle": _on_shank(knee, ankle, ankle_at, skins["shank"]),
        "calf": _on_shank(knee, ankle, calf_at, skins["shank"]),
        "knee": (knee, unit(unit(knee - hip) + shank), knee, skins["knee"]),
    }
    for name in ("thigh", "hip", "waist"):
        origin, normal, centre = trunk[f"{name}_girth"]
        planes[name] = (origin, normal, centre, tape_skin(body).get(f"{name}_girth"))
    return planes


def level_tapes(body: Body, vertices: np.ndarray, posed: JointSet) -> dict[str, Tape]:
    """The tape (girth and hull path) at each level in a posture."""
    topo = topology(body.faces)
    return {name: tape_girth(vertices, topo, o, n, c, part=skin)
            for name, (o, n, c, skin) in level_planes(body, vertices, posed).items()}


def shank_levels(body: Body) -> tuple[float, float]:
    """Fractions of knee → ankle joint of the ankle (least girth) and calf (greatest girth) levels."""
    found = _SHANK.get(body)
    if found is None:
        joints = JointSet(body.rig.names, body.rig.heads)
        knee, ankle = joints["lowerleg01.R"], joints["foot.R"]
        topo, skin = topology(body.faces), _skins(body)["shank"]
        picks = []
        for (low, high), pick in ((ANKLE_RANGE, np.argmin), (CALF_RANGE, np.argmax)):
            fractions = np.linspace(low, high, SCAN)
            girths = [tape_girth(body.vertices, topo, *_on_shank(knee, ankle, f, skin)[:3], part=skin).girth
                      for f in fractions]
            picks.append(float(fractions[pick(np.nan_to_num(girths, nan=np.nanmean(girths)))]))
        found = (picks[0], picks[1])
        _SHANK[body] = found
    return found


def _on_shank(knee: np.ndarray, ankle: np.ndarray, fraction: float, skin: np.ndarray) -> Plane:
    point = knee + fraction * (ankle - knee)
    return point, unit(ankle - knee), point, skin


def _skins(body: Body) -> dict[str, np.ndarray]:
    out = {}
    for key, bones in (("shank", SHANK_SKIN), ("knee", KNEE_SKIN)):
        columns = [body.rig.index(b) for b in bones]
        out[key] = np.asarray(body.skin_weights[:, columns].sum(axis=1)).ravel() >= MAIN_WEIGHT
    return out

