"""What a pose did, in a few lines a person reads: which joints moved, by how much, in degrees.

One line per request entry: a muscle names its contraction and the joint
angles it set (a muscle over many joints, e.g. along the spine, in one line),
an --angle its DOF. Angles are clinical (0 = anatomical position), so the
rest pose's bend (an A-pose elbow at about 40°) shows as the starting value.
"""

from __future__ import annotations

import numpy as np

from hitogata.commands.pose_args import PoseRequest
from hitogata.posing.pose import PosedBody
from hitogata.skeleton.shoulder import channel_names, girdle_dofs

MOVED = np.radians(0.05)  # smaller changes are not reported


def _dof_line(posed: PosedBody, k: int) -> str:
    sk = posed.skeleton
    rest, change = np.degrees(sk.rest[k]), np.degrees(posed.angles[k])
    return f"{sk.dof_names[k]} {rest:.1f}° → {rest + change:.1f}° ({change:+.1f}°)"


def _muscle_cause(request: PoseRequest, posed: PosedBody, name: str) -> str:
    if name in request.lengths:
        rest = posed.muscles.rest_length[posed.muscles.index(name)]
        return f"{name} at {request.lengths[name] * 100:.1f} cm (rest {rest * 100:.1f} cm)"
    c = request.contractions[name]
    return f"{name} {'contracted' if c >= 0 else 'stretched'} {abs(c) * 100:.1f}%"


def _muscle_effect(posed: PosedBody, name: str) -> str:
    sk, ms = posed.skeleton, posed.muscles
    dofs = ms.dofs(ms.index(name))
    if len(dofs) == 1:
        return _dof_line(posed, int(dofs[0]))
    change = np.degrees(posed.angles[dofs])
    parts = f"{sk.dof_names[dofs[0]].split('.')[0]}…{sk.dof_names[dofs[-1]].split('.')[0]}"
    what = f"{sk.dof_names[dofs[0]].split('.')[1]} of {len(dofs)} joints {parts}"
    if np.allclose(change, change[0], atol=1e-6):
        return f"{what}, each {change[0]:+.1f}°"
    return f"{what}, {change.sum():+.1f}° in all ({change.min():+.1f}…{change.max():+.1f}° each)"


def _complex_line(request: PoseRequest, posed: PosedBody, name: str) -> str:
    """A shoulder-complex control and the joint angles the rhythm gave it."""
    sk, side = posed.skeleton, name.split(".")[0][-1]
    joints = "; ".join(_dof_line(posed, k) for k in girdle_dofs(sk, side))
    return f"{name} {np.degrees(request.clinical[name]):.1f}° (shoulder complex): {joints}"


def pose_summary(request: PoseRequest, posed: PosedBody) -> list[str]:
    """Indented lines, one per muscle and angle of the request; 'rest pose' when nothing moved."""
    lines = [
        f"  {_muscle_cause(request, posed, name)}: {_muscle_effect(posed, name)}"
        for name in [*request.contractions, *request.lengths]
    ]
    sk = posed.skeleton
    complexes = channel_names(sk)
    for name in request.clinical:
        said = _complex_line(request, posed, name) if name in complexes else _dof_line(posed, sk.dof_index(name))
        lines.append(f"  --angle {said}")
    if not lines:
        return ["  rest pose (MakeHuman A-pose): no muscle or angle given"]
    return lines


def moved_count(posed: PosedBody) -> int:
    """How many DOFs differ from the rest pose."""
    return int(np.count_nonzero(np.abs(posed.angles) > MOVED))
