"""Where a garment's girths lie on the body: the leg levels of compression hosiery and the trunk's.

RAL-GZ 387-1 measures a stocking's pressure at named levels of the leg:
B (the ankle: the least girth above the malleoli), C (the calf: its greatest
girth), D (below the knee), E (the knee), G (the top of the thigh). These are
ISO 8559-1 girths that `hitogata.measure` takes (`girth_planes`): ankle and
calf ⊥ the shank at the levels of its least and greatest girth (found once
on the rest body, continuous in shape), the knee through the knee joint ⊥ the
bisector of thigh and shank, thigh, hip and waist as measured; each round its
own part's skin (`tape_skin`). Right side, as the measurements.
"""

from __future__ import annotations

import numpy as np

from hitogata.body.model import Body
from hitogata.measure.axes import JointSet
from hitogata.measure.landmarks import body_landmarks
from hitogata.measure.measurements import girth_planes, tape_skin
from hitogata.measure.sections import Tape, tape_girth
from hitogata.geometry.topology import topology

LEVELS = ("ankle", "calf", "knee", "thigh", "hip", "waist")

Plane = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None]  # origin, normal, centre, skin mask


def level_planes(body: Body, vertices: np.ndarray, posed: JointSet) -> dict[str, Plane]:
    """The six levels' planes in a posture (vertices (V, 3), posed rig joint centres)."""
    rest = JointSet(body.rig.names, body.rig.heads)
    planes, skins = girth_planes(vertices, body_landmarks(body), rest, posed), tape_skin(body)
    return {name: (*planes[f"{name}_girth"], skins.get(f"{name}_girth")) for name in LEVELS}


def level_tapes(body: Body, vertices: np.ndarray, posed: JointSet) -> dict[str, Tape]:
    """The tape (girth and hull path) at each level in a posture."""
    topo = topology(body.faces)
    return {name: tape_girth(vertices, topo, o, n, c, part=skin)
            for name, (o, n, c, skin) in level_planes(body, vertices, posed).items()}
