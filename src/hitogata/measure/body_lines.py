"""Named lines drawn on a body's rest skin where garments are cut from the skin's stretch.

Each line is 10 cm long along its limb or across its zone, centred on a
joint, placed from the MakeHuman rig at rest (left side):
- `elbow_posterior`, `elbow_anterior`, `knee_anterior`, `knee_posterior`: along the limb over
  the joint's extensor or flexor side (the plane holding the limb's axis —
  shoulder→wrist, hip→ankle — and the side's direction);
- `elbow_circumference`, `knee_circumference`: round the limb, in the plane
  through the joint normal to the limb's axis;
- `back_width`: across the back between the posterior armpit folds (a
  horizontal line 0.045 × stature below the shoulder joints, between the
  folds at 0.8 of the shoulder joints' half-spacing);
- `seat_vertical`: up the left buttock through the hip joint's height, in
  the sagittal plane through the hip joint.
"""

from __future__ import annotations

import numpy as np

from hitogata.body.model import Body
from hitogata.measure.skin_lines import SkinLine, draw_line

HALF = 0.05  # m: half of a 10 cm line
FOLD_DROP = 0.045  # × stature: the posterior armpit folds below the shoulder joints
FOLD_SPREAD = 0.8  # of the shoulder joints' half-spacing
LINE_NAMES = (
    "elbow_posterior", "elbow_anterior", "elbow_circumference", "knee_anterior", "knee_posterior",
    "knee_circumference", "back_width", "seat_vertical",
)
BACK = np.array([0.0, 0.0, -1.0])


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def _along(vertices, faces, joint, axis, side) -> SkinLine:
    side = _unit(side - (side @ axis) * axis)
    return draw_line(
        vertices, faces, joint, np.cross(axis, side),
        lambda p: ((p - joint) @ side > 0.0) & (np.abs((p - joint) @ axis) <= HALF),
    )


def _round(vertices, faces, joint, axis) -> SkinLine:
    return draw_line(vertices, faces, joint, axis, lambda p: np.linalg.norm(p - joint, axis=1) < 0.2)


def body_lines(body: Body, vertices: np.ndarray | None = None, faces: np.ndarray | None = None) -> dict[str, SkinLine]:
    """The named lines on the body's rest skin, or on another rest surface of it (e.g. the fine skin)."""
    v = body.vertices if vertices is None else vertices
    f = body.faces if faces is None else faces

    def head(bone: str) -> np.ndarray:
        return body.rig.heads[body.rig.index(bone)]

    elbow, knee = head("lowerarm01.L"), head("lowerleg01.L")
    arm = _unit(head("wrist.L") - head("upperarm01.L"))
    leg = _unit(head("foot.L") - head("upperleg01.L"))
    shoulders = np.array([head("upperarm01.L"), head("upperarm01.R")])
    fold = shoulders.mean(axis=0) - np.array([0.0, FOLD_DROP * body.stature, 0.0])
    reach = FOLD_SPREAD * 0.5 * abs(shoulders[0, 0] - shoulders[1, 0])
    hip = head("upperleg01.L")
    return {
        "elbow_posterior": _along(v, f, elbow, arm, BACK),
        "elbow_anterior": _along(v, f, elbow, arm, -BACK),
        "elbow_circumference": _round(v, f, elbow, arm),
        "knee_anterior": _along(v, f, knee, leg, -BACK),
        "knee_posterior": _along(v, f, knee, leg, BACK),
        "knee_circumference": _round(v, f, knee, leg),
        "back_width": draw_line(
            v, f, fold, np.array([0.0, 1.0, 0.0]),
            lambda p: (p[:, 2] < fold[2]) & (np.abs(p[:, 0] - fold[0]) <= reach),
        ),
        "seat_vertical": draw_line(
            v, f, hip, np.array([1.0, 0.0, 0.0]),
            lambda p: (p[:, 2] < hip[2]) & (np.abs(p[:, 1] - hip[1]) <= HALF),
        ),
    }
