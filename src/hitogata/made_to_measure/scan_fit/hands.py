"""A coarse search of each hand's turn and each finger's bend before the Gauss–Newton steps refine them.

A hand turned at the forearm and bent at the wrist is a flat paddle that
point-to-plane steps from the hanging hand can settle a part-turn short, palm
matched to the back of the hand; fingers lying side by side pair with their
neighbours' scan points, and a finger bent the wrong way then pulls the wrist
after it. So when the forearms join the fit the wrist's three angles (the
forearm's pronation, the wrist's flexion and deviation), and when the fingers
join the wrist's and each finger's three in turn, twice over, are tried on a grid about their current values
(`Poser.pose_many`, both sides at once), then on a narrower grid about the
best (`SCALES`). A candidate's score is the mean distance of the moved part's
skin to its nearest scan points plus that of the scan points about the hand to
the candidate's hand and arm skin, each distance clipped at `register.CLIP` so
that a far stray point does not decide.
"""

from __future__ import annotations

import itertools

import numpy as np
from scipy.spatial import cKDTree

from hitogata.made_to_measure.scan_fit.model import FINGERS, POSE_NAMES, BodyModel
from hitogata.posing.body_split import owning_parts
from hitogata.posing.pose import Poser
from hitogata.posing.skinning import skin_vertices

SIDES = ("l", "r")
# (the skeleton parts whose skin is scored, the pose entries and their offsets tried, degrees)
WRIST = (("hand_{s}",), {"forearm_{s}.pronation": (-60.0, -40.0, -20.0, 0.0, 20.0, 40.0, 60.0),
                         "hand_{s}.flexion": (-30.0, 0.0, 30.0), "hand_{s}.radial_deviation": (-15.0, 0.0, 15.0)})
DIGITS = (
    (("thumb_metacarpal_{s}", "thumb_phalanges_{s}"),
     {"thumb_metacarpal_{s}.flexion": (-15.0, 0.0, 15.0), "thumb_metacarpal_{s}.abduction": (-30.0, -15.0, 0.0, 15.0, 30.0),
      "thumb_phalanges_{s}.flexion": (-20.0, 0.0, 20.0)}),
    *(((f"{f}_proximal_{{s}}", f"{f}_distal_{{s}}"),
       {f"{f}_proximal_{{s}}.flexion": (-30.0, -15.0, 0.0, 15.0, 30.0, 45.0),
        f"{f}_proximal_{{s}}.abduction": (-10.0, 0.0, 10.0),
        f"{f}_distal_{{s}}.flexion": (-20.0, 0.0, 20.0, 40.0)}) for f in FINGERS),
)
HAND_PARTS = ("hand_{s}", *(p for parts, _ in DIGITS for p in parts))
ARM_PARTS = ("upper_arm_{s}", "forearm_{s}", *HAND_PARTS)
REACH = 0.1  # m: the scan points this near the hand's skin as it stands are the hand's, whatever its turn
SCALES = (1.0, 0.4, 0.15)  # the grid's spread in turn, each time about the best of the wider grid
SWEEPS = 2  # wrist then fingers, again: a wrist searched with the fingers straight bends to make up for them


def search_hands(model: BodyModel, poser: Poser, pose: np.ndarray, points: np.ndarray, clip: float,
                 fingers: bool) -> np.ndarray:
    """The pose with each wrist's angles (and, with `fingers`, each finger's) the best of their grids for the
    scan points (P, 3) in the body frame."""
    q = model.angles(poser, pose)
    part = owning_parts(poser.skin.weights)
    names = poser.skeleton.names
    arms = np.flatnonzero(np.isin(part, [names.index(t.format(s=s)) for t in ARM_PARTS for s in SIDES]))
    arm_skin = poser.skin.part(arms)  # the candidates move nothing else: only the arms' skin is posed

    def pose_arms(angles: np.ndarray) -> np.ndarray:
        kin = poser.kinematics.pose(angles)
        return skin_vertices(arm_skin, kin.rotations, kin.translations)

    def skin(templates: tuple[str, ...], side: str) -> np.ndarray:
        """The arms' skin (indices into `arms`) of the parts `templates` on one side."""
        return np.flatnonzero(np.isin(part[arms], [names.index(t.format(s=side)) for t in templates]))

    now = pose_arms(q[None])[0]
    tree = cKDTree(points)
    about = {}
    for side in SIDES:
        hand = now[skin(HAND_PARTS, side)]
        about[side] = points[cKDTree(hand).query(points, distance_upper_bound=REACH)[0] < REACH]
    out = pose.copy()
    for parts, grid in (WRIST, *DIGITS) * SWEEPS if fingers else (WRIST,):
        for scale in SCALES:
            candidates = _candidates(model, out, grid, scale)
            surfaces = pose_arms(np.stack([model.moved_angles(poser, pose, q, p) for p in candidates]))
            for side in SIDES:
                moved = surfaces[:, skin(parts, side)].reshape(-1, 3)
                score = tree.query(moved, distance_upper_bound=clip)[0].reshape(len(candidates), -1)
                score = np.minimum(score, clip).mean(axis=1)
                if len(about[side]):
                    score += np.minimum(_nearest_skin(surfaces[:, skin(ARM_PARTS, side)], about[side], clip),
                                        clip).mean(axis=1)
                index = [POSE_NAMES.index(t.format(s=side)) for t in grid]
                out[index] = candidates[int(np.argmin(score)), index]
    return out


def _nearest_skin(surfaces: np.ndarray, points: np.ndarray, clip: float) -> np.ndarray:
    """(C, P) each point's distance to the nearest of each candidate's skin vertices (C, A, 3), exact up to
    `clip` (inf beyond). The skin no candidate moves is searched once; only the moving rest per candidate."""
    still = np.all(surfaces == surfaces[:1], axis=(0, 2))
    fixed = np.full(len(points), np.inf)
    if still.any():
        fixed = cKDTree(surfaces[0, still]).query(points, distance_upper_bound=clip)[0]
    if still.all():
        return np.tile(fixed, (len(surfaces), 1))
    return np.stack([np.minimum(fixed, cKDTree(s).query(points, distance_upper_bound=clip)[0])
                     for s in surfaces[:, ~still]])


def _candidates(model: BodyModel, pose: np.ndarray, grid: dict[str, tuple[float, ...]], scale: float) -> np.ndarray:
    """(C, Q) the pose with the grid's offsets, times `scale`, on both sides alike, within the bounds."""
    lo, hi = model.pose_bounds
    index = [POSE_NAMES.index(t.format(s=side)) for side in SIDES for t in grid]
    offsets = np.radians(list(itertools.product(*grid.values()))) * scale
    candidates = np.repeat(pose[None], len(offsets), axis=0)
    candidates[:, index] = np.clip(pose[index] + np.tile(offsets, len(SIDES)), lo[index], hi[index])
    return candidates
