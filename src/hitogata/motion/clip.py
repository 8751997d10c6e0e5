"""A skeleton motion: joint angles over time and the whole body's rigid motion (root)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.motion.scenario import Scenario
from hitogata.errors import HitogataError
from hitogata.posing.pose import Poser


@dataclass(frozen=True)
class MotionClip:
    """times (F,) s; angles (F, D) rest-relative radians; root (F, 4, 4) the pelvis's rigid motion
    (rest → posed, applied to the whole skeleton: walking forward, turning)."""

    times: np.ndarray
    angles: np.ndarray
    root: np.ndarray

    @property
    def rate(self) -> float:
        """Frames per second."""
        return 1.0 / float(self.times[1] - self.times[0]) if len(self.times) > 1 else 30.0


def still_root(frames: int) -> np.ndarray:
    """(F, 4, 4) identities: a body that stays where it stands."""
    return np.broadcast_to(np.eye(4), (frames, 4, 4)).copy()


def scenario_clip(scenario: Scenario, poser: Poser, rate: float | None = None) -> MotionClip:
    """The skeleton motion of a scenario: its channels sampled at `rate` (default the scenario's),
    muscles turned into joint angles by eq. 1, 2 — the skeleton `hitogata simulate` moves."""
    rate = scenario.rate if rate is None else rate
    if not (np.isfinite(rate) and 1 <= rate <= 240):
        raise HitogataError(f"rate {rate!r} frames per second: allowed 1..240")
    times = np.arange(int(round(scenario.duration * rate)) + 1) / rate
    sk = poser.skeleton
    rest = {("clinical", c.name): float(sk.rest[sk.dof_index(c.name)])
            for c in scenario.timeline.channels if c.kind == "clinical"}
    channels = scenario.timeline.sample(times, rest)
    angles = np.empty((len(times), sk.n_dofs))
    for i in range(len(times)):
        pick = {kind: {name: float(v[i]) for name, v in values.items()} for kind, values in channels.items()}
        angles[i] = poser.angles(contractions=pick["contraction"] or None, angles=pick["angle"] or None,
                                 clinical=pick["clinical"] or None, on_limit=scenario.on_limit)
    root = still_root(len(times)) if scenario.root is None else scenario.root.sample(times)
    return MotionClip(times, angles, root)


def peak_clip(clip: MotionClip) -> MotionClip:
    """Standing, then the clip's frame furthest from its first in joint angles (the motion's peak posture), one
    second apart: the two postures a motion's largest changes come from."""
    k = int(np.argmax(np.linalg.norm(clip.angles - clip.angles[0], axis=1)))
    return MotionClip(np.array([0.0, 1.0]), clip.angles[[0, k]], clip.root[[0, k]])
