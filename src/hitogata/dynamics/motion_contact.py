"""Self-contact through a motion (IPC in time): no frame's skin passing into another part of the body.

Each frame's skin as the motion computes it (its elastic offset already held
back where it would fold or cross beyond skinning's: `geometry.offset_limit`)
is the target y_k of the barrier problem of `hitogata.geometry.barrier_contact`,
started from the previous frame's resolved skin x_{k−1}. Consecutive frames
are close, so each solve is short, and the continuous collision detection of
every Newton step keeps each frame free of crossings among the skin the
barrier sees; where the frame crosses skin the barrier does not hold
apart, it is held back towards the previous frame, as a held pose is
towards its last step's start (`dynamics.contact.hold_back_crossings`).
The first frame is reached from the rest skin through skinned postures on
the way (`dynamics.contact.approach`).

A vertex not free takes its target, so skin freed at one frame and not at the
next would jump there unchecked: frame k's path is [x_{k−1}, y_{k−1}, y_k], and
its free skin (the skin near contacts, `barrier_contact.contact_region`) that
of both targets; freed skin is let go over one more solve. A frame whose free
skin lies nowhere near a contact takes its target as it is (no barrier). If the
previous frame's skin crosses itself where the frame's free skin lies (skin
that was not free, at its target), the frame is reached from rest instead.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from hitogata.dynamics.contact import FOLDING, approach, hold_back_crossings
from hitogata.geometry.barrier_contact import DHAT, barrier_resolve, contact_region

if TYPE_CHECKING:
    from hitogata.dynamics.motion import BodyDynamics


@dataclass(frozen=True)
class MotionContact:
    """What resolving a motion's self-contact took, per frame (F,)."""

    free: np.ndarray  # free skin vertices (0: nothing near a contact, the frame's skin as it was)
    iterations: np.ndarray  # Newton iterations, all steps of the frame's path
    seconds: np.ndarray  # wall time of the frame's contact
    from_rest: np.ndarray  # bool: reached from the rest skin (the first frame, or a restart)
    min_distance: np.ndarray  # m: the smallest gap left between skin that may meet (DHAT where none is near)


def resolve_frames(dynamics: BodyDynamics, skins: np.ndarray, angles: np.ndarray,
                   roots: np.ndarray | None = None, progress: Callable[[int], None] | None = None
                   ) -> tuple[np.ndarray, MotionContact]:
    """The frames' skins (F, V, 3) with their self-contact resolved (float32), and what it took.

    angles: (F, D) the frames' joint angles; roots: (F, 4, 4) the whole body's transform per frame
    (None: it stands where it is); progress(frames done) after each frame."""
    n = len(skins)
    out = np.empty_like(skins, dtype=np.float32)
    free, iterations, from_rest = np.zeros(n, dtype=int), np.zeros(n, dtype=int), np.zeros(n, dtype=bool)
    seconds, gap = np.zeros(n), np.full(n, DHAT)
    previous = None
    for k in range(n):
        start = time.perf_counter()
        y = skins[k].astype(float)
        if previous is None:
            path, from_rest[k] = _from_rest(dynamics, angles[k], None if roots is None else roots[k], y), True
        else:
            path = [previous, skins[k - 1].astype(float), y]
        region = contact_region(path[1:], dynamics.contact)
        if region.any():
            try:
                result = barrier_resolve(path, dynamics.contact, folding=FOLDING)
            except ValueError:  # the previous frame's skin crosses where this frame's free skin lies
                path, from_rest[k] = _from_rest(dynamics, angles[k], None if roots is None else roots[k], y), True
                result = barrier_resolve(path, dynamics.contact, folding=FOLDING)
            # held back towards the previous frame (free of crossings), or from rest the last step's start
            previous, _ = hold_back_crossings(dynamics, result.vertices,
                                              result.before_last if from_rest[k] else path[0])
            free[k], iterations[k], gap[k] = result.free.sum(), sum(result.iterations), result.min_distance
        else:
            previous = y
        out[k] = previous
        seconds[k] = time.perf_counter() - start
        if progress is not None:
            progress(k + 1)
    return out, MotionContact(free, iterations, seconds, from_rest, gap)


def _from_rest(dynamics: BodyDynamics, angles: np.ndarray, root: np.ndarray | None, skin: np.ndarray
               ) -> list[np.ndarray]:
    """The barrier's path to a frame's skin from the rest skin: straight there at rest, else through
    the frame's posture skinned on the way."""
    if not angles.any() and root is None:
        return [dynamics.poser.body.vertices, skin]
    return [*approach(dynamics.poser, angles, dynamics.rig.method, root), skin]
