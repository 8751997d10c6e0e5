"""The first rigid alignment of a scan to the body: principal axes, every way round, the best kept.

A scan may come in any orientation (Z up, facing away, …). The principal axes
of the scan and of the body are matched in each of the 24 proper ways (which
scan axis is which body axis, and their signs), in the rest pose and with the
arms raised to a T; each candidate gets a few rigid-only registration steps on
a small sample, and the one closest to the body wins.
"""

from __future__ import annotations

import itertools

import numpy as np
from threadpoolctl import threadpool_limits

from hitogata.made_to_measure.scan_fit.model import POSE_NAMES, T_POSE, BodyModel
from hitogata.made_to_measure.scan_fit.register import SIGMA, Registration, Surface, gauss_newton_step
from hitogata.posing.pose import poser_for

ALIGN_POINTS = 800  # scan points per candidate
ALIGN_STEPS = 3  # rigid-only iterations per candidate and round
KEEP = 4  # candidates refined in the second round
ALIGN_EVERY = 8  # every 8th body vertex pulls towards the scan while aligning


def principal_axes(points: np.ndarray) -> np.ndarray:
    """(3, 3) unit principal axes as columns, largest spread first, right-handed (a rotation, never a mirror)."""
    centred = points - points.mean(axis=0)
    _, vectors = np.linalg.eigh(centred.T @ centred)
    axes = vectors[:, ::-1].copy()
    if np.linalg.det(axes) < 0:
        axes[:, 2] *= -1
    return axes


def axis_matchings() -> list[np.ndarray]:
    """The 24 proper rotations that map one orthonormal frame's axes onto another's."""
    out = []
    for perm in itertools.permutations(range(3)):
        for signs in itertools.product((1.0, -1.0), repeat=3):
            m = np.zeros((3, 3))
            m[list(perm), range(3)] = signs
            if np.linalg.det(m) > 0:
                out.append(m)
    return out


def arm_poses(model: BodyModel) -> list[np.ndarray]:
    """The start poses tried: the rest pose's arms and a T-pose's."""
    rest = model.pose_start()
    t_pose = rest.copy()
    for side in ("l", "r"):
        t_pose[POSE_NAMES.index(f"shoulder_{side}.abduction")] = T_POSE
    return [rest, t_pose]


def initial_alignments(model: BodyModel, points: np.ndarray, seed: int = 0) -> list[Registration]:
    """The best rigid starts (and arm poses) for a scan (P, 3) in metres, in any orientation, best first.

    Every candidate takes `ALIGN_STEPS` rigid steps; the `KEEP` best take as many again.
    A body facing the wrong way differs mostly at the feet and face, which a rigid
    fit of the average body cannot always tell: the caller tries the first few further.
    """
    with threadpool_limits(1, user_api="blas"):  # small solves: a second BLAS thread only spins
        return _alignments(model, points, seed)


def _alignments(model: BodyModel, points: np.ndarray, seed: int) -> list[Registration]:
    rng = np.random.default_rng(seed)
    sample = points[rng.choice(len(points), min(ALIGN_POINTS, len(points)), replace=False)]
    shape = model.shape_start()
    scan_axes, scan_centre = principal_axes(points), points.mean(axis=0)
    candidates: list[tuple[float, Registration, Surface]] = []
    body = model.body(shape)
    for pose in arm_poses(model):
        posed, _ = model.posed(poser_for(body), pose)
        surface = Surface.of(posed, body.faces, every=ALIGN_EVERY)
        body_axes, body_centre = principal_axes(posed), posed.mean(axis=0)
        for matching in axis_matchings():
            rotation = body_axes @ matching @ scan_axes.T
            start = Registration(rotation, body_centre - rotation @ scan_centre, shape, pose)
            candidates.append((*_rigid(model, sample, start, surface), surface))
    candidates.sort(key=lambda c: c[0])
    refined = [_rigid(model, sample, found, surface) for _, found, surface in candidates[:KEEP]]
    return [found for _, found in sorted(refined, key=lambda c: c[0])]


def _rigid(model: BodyModel, points: np.ndarray, start: Registration, surface: Surface) -> tuple[float, Registration]:
    """`ALIGN_STEPS` rigid-only steps on a fixed surface; the score (`register.score`) and the registration."""
    state, score = start, np.inf
    for _ in range(ALIGN_STEPS):
        state, score = gauss_newton_step(model, points, state, surface, SIGMA[0])
    return score, state
