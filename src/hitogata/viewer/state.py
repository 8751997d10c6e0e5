"""The viewer's posing state: which muscle drives which joint, and the body in its current pose.

No viser here: the GUI and the scene only read and change this object, so
it is tested without a browser. A slider sets one muscle's contraction; as
in the library (one given muscle per DOF), a muscle moved last takes over the
DOFs it shares with earlier ones (its antagonist, its bilateral twin for the
spine), and every other muscle's contraction follows from the joint angles.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from hitogata.body.model import Body
from hitogata.muscles.activation import contractions_of
from hitogata.muscles.geometry import MuscleSet
from hitogata.posing.pose import PosedBody, Poser, poser_for

SLIDER_STEP = 0.1  # percent of the rest length


@dataclass(frozen=True)
class MuscleRanges:
    """Per muscle, the contractions (percent of rest length) that span its joints' range of motion."""

    low: np.ndarray  # (M,)
    high: np.ndarray  # (M,)


def muscle_ranges(muscles: MuscleSet) -> MuscleRanges:
    """Contractions at the two ends of each muscle's range of motion, rounded inwards to the slider step.

    Rounding inwards keeps every slider position inside the joints' limits, so a
    slider never asks for a pose the library refuses.
    """
    def joint_angles(theta: np.ndarray) -> np.ndarray:
        t = theta[:, None]
        return np.maximum(t, 0.0) * muscles.share_pos + np.minimum(t, 0.0) * muscles.share_neg

    at_low = np.diag(contractions_of(muscles, joint_angles(muscles.low)))
    at_high = np.diag(contractions_of(muscles, joint_angles(muscles.high)))
    lo, hi = np.minimum(at_low, at_high) * 100.0, np.maximum(at_low, at_high) * 100.0
    scale = 1.0 / SLIDER_STEP
    low, high = np.ceil(lo * scale - 1e-6) / scale, np.floor(hi * scale + 1e-6) / scale
    return MuscleRanges(low=low + 0.0, high=high + 0.0)  # + 0.0: no -0.0 on a slider


class PoseState:
    """A body, its prepared Poser, the driving muscles and the current pose."""

    def __init__(self, body: Body) -> None:
        self.drivers: dict[str, float] = {}
        self._use(body)
        self.posed = self.poser.pose()

    def _use(self, body: Body) -> None:
        self.body = body
        self.poser: Poser = poser_for(body)
        self.ranges = muscle_ranges(self.poser.muscles)

    @property
    def muscles(self) -> MuscleSet:
        return self.poser.muscles

    def set_contraction(self, name: str, fraction: float) -> PosedBody:
        """Drive `name` at a contraction (fraction of rest length); it takes over the DOFs it shares.

        A contraction the muscle cannot reach raises `HitogataError` and leaves the pose unchanged.
        """
        ms = self.muscles
        moved = set(ms.dofs(ms.index(name)).tolist())
        drivers = {
            other: value
            for other, value in self.drivers.items()
            if other != name and not moved & set(ms.dofs(ms.index(other)).tolist())
        }
        drivers[name] = float(fraction)
        posed = self.poser.pose(contractions=drivers)
        self.posed, self.drivers = posed, drivers  # posed first: readers wait on drivers
        return posed

    def reset(self) -> PosedBody:
        """Back to the rest pose: no muscle drives."""
        self.posed = self.poser.pose()
        self.drivers = {}
        return self.posed

    def set_body(self, body: Body) -> PosedBody:
        """Use another body, keeping the joint angles; the drivers' contractions are re-read on it."""
        angles = self.posed.angles
        self._use(body)
        self.posed = self.poser.pose(angles=angles)
        now = self.contractions()
        self.drivers = {name: float(now[self.muscles.index(name)]) for name in self.drivers}
        return self.posed

    def contractions(self) -> np.ndarray:
        """(M,) every muscle's contraction (fraction of rest length) in the current pose."""
        return contractions_of(self.muscles, self.posed.angles)[0]

    def slider_values(self) -> Mapping[str, float]:
        """Muscle name → its contraction in percent, rounded to the slider step."""
        percent = np.round(self.contractions() * 100.0 / SLIDER_STEP) * SLIDER_STEP + 0.0  # no -0.0
        return dict(zip(self.muscles.names, percent.tolist()))
