"""Self-contact through a motion (IPC in time): no frame's skin passing into another part of the body.

Each frame's skin as the motion computes it (its elastic offset already held
back where it would fold or cross beyond skinning's: `geometry.offset_limit`),
its creases tied back towards skinning's fold as a held pose's are
(`skin.creases`), is the target y_k of the barrier problem of
`hitogata.geometry.barrier_contact`, started from the previous frame's resolved
skin x_{k−1}. Consecutive frames are close, so each solve is short, and the
continuous collision detection of every Newton step keeps each frame free of
crossings among the skin the barrier sees; where the frame crosses skin the
barrier does not hold apart, it is held back towards the previous frame, as a
held pose is towards its last step's start (`skin.contact.hold_back_crossings`).
The first frame is reached from the rest skin through skinned postures on
the way (`skin.contact.approach`).

A vertex not free takes its target, so skin freed at one frame and not at the
next would jump there unchecked: frame k's path is [x_{k−1}, y_{k−1}, y_k], and
its free skin (the skin near contacts, `barrier_contact.contact_regions`) at
its second step that of both targets; freed skin is let go over one more
solve. A frame whose free skin lies nowhere near a contact takes its target
as it is (no barrier). If the
previous frame's skin crosses itself where the frame's free skin lies (skin
that was not free, at its target), the frame is reached from rest instead.

`simulate` is the motion of the elastic body (`hitogata.dynamics.simulate`) with, on `contact`, this
resolution handed in (the dynamics take it as a `FrameContact` and know nothing of the skin's contact):
the front door's `hitogata.simulate`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from functools import partial

import numpy as np

from hitogata.dynamics import motion
from hitogata.dynamics.motion import ITERATIONS, BodyDynamics, Motion, MotionContact
from hitogata.dynamics.timeline import RootTrack, Timeline
from hitogata.geometry.barrier_contact import contact_regions
from hitogata.options import OnLimit
from hitogata.skin.contact import approach, skin_contact, skin_limiter
from hitogata.skin.creases import solve_creased
from hitogata.skin.settings import SKIN_DEFAULTS, SkinSettings


def simulate(dynamics: BodyDynamics, timeline: Timeline, duration: float, rate: float, substeps: int = 1,
             gravity: bool = True, on_limit: OnLimit = "raise", iterations: int = ITERATIONS,
             progress: Callable[[int, int], None] | None = None, root: RootTrack | None = None,
             contact: bool = False, settings: SkinSettings = SKIN_DEFAULTS) -> Motion:
    """Run a timeline for `duration` seconds (`hitogata.dynamics.simulate`: outputs at `rate` frames per second,
    `substeps` steps per frame; progress(done, total) after each step and each frame's contact; root: the whole
    body's rigid motion, None: it stands where it is); contact: every frame's skin with no part of it passing
    into another and its creases folded as a held pose's (`resolve_frames`, 0.1-0.4 s a frame where skin
    meets); settings: the skin's contact constants (`skin.settings`), for the frames' offset limit and contact."""
    frame_contact = partial(resolve_frames, settings=settings) if contact else None
    return motion.simulate(dynamics, timeline, duration, rate, substeps, gravity, on_limit, iterations, progress,
                           root, frame_contact, skin_limiter(dynamics, settings))


def resolve_frames(dynamics: BodyDynamics, skins: np.ndarray, skinned: np.ndarray, rotations: np.ndarray,
                   angles: np.ndarray, roots: np.ndarray | None = None, progress: Callable[[int], None] | None = None,
                   settings: SkinSettings = SKIN_DEFAULTS) -> tuple[np.ndarray, MotionContact]:
    """The frames' skins (F, V, 3) with their self-contact resolved and their creases folded (float32), and
    what it took.

    skinned: (F, V, 3) the frames' skins by skinning alone; rotations: (F, parts, 3, 3) the parts' rotations;
    angles: (F, D) the frames' joint angles; roots: (F, 4, 4) the whole body's transform per frame (None: it
    stands where it is); progress(frames done) after each frame; settings: the contact's constants."""
    n = len(skins)
    out = np.empty_like(skins, dtype=np.float32)
    free, iterations, from_rest = np.zeros(n, dtype=int), np.zeros(n, dtype=int), np.zeros(n, dtype=bool)
    test, barrier = skin_contact(dynamics.poser, settings.penetration), settings.barrier
    seconds, gap = np.zeros(n), np.full(n, barrier.dhat)
    previous = target = np.zeros(0)
    for k in range(n):
        start = time.perf_counter()
        y, plain = skins[k].astype(float), skinned[k].astype(float)
        root = None if roots is None else roots[k]
        if k == 0:
            before, from_rest[k] = _from_rest(dynamics, angles[k], root, settings), True
        else:
            before = [previous, target]  # the last frame's skin and the target it was given
        region = contact_regions([*before[1:], y], test, barrier.reach, barrier.rings)
        if region[-1].any():
            try:  # held back towards the last frame's skin (free of crossings), or from rest the last step's start
                solved = solve_creased(dynamics, before, plain, y - plain, rotations[k], region,
                                       None if from_rest[k] else previous, settings)
            except ValueError:  # the last frame's skin crosses where this frame's free skin lies
                before, from_rest[k] = _from_rest(dynamics, angles[k], root, settings), True
                region = contact_regions([*before[1:], y], test, barrier.reach, barrier.rings)
                solved = solve_creased(dynamics, before, plain, y - plain, rotations[k], region, settings=settings)
            previous, target = solved.skin, solved.target
            result = solved.barrier
            free[k], iterations[k], gap[k] = result.free.sum(), sum(result.iterations), result.min_distance
        else:
            previous = target = y
        out[k] = previous
        seconds[k] = time.perf_counter() - start
        if progress is not None:
            progress(k + 1)
    return out, MotionContact(free, iterations, seconds, from_rest, gap)


def _from_rest(dynamics: BodyDynamics, angles: np.ndarray, root: np.ndarray | None, settings: SkinSettings
               ) -> list[np.ndarray]:
    """The barrier's path from the rest skin to a frame's posture, but the frame's own skin: the rest skin, and
    unless the frame stands at rest the frame's posture skinned on the way."""
    if not angles.any() and root is None:
        return [dynamics.poser.body.vertices]
    return approach(dynamics.poser, angles, dynamics.rig.method, root, settings)
