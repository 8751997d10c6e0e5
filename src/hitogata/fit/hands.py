"""A coarse search of each hand's turn before the Gauss–Newton steps refine it.

A hand turned at the forearm and bent at the wrist is a flat paddle that
point-to-plane steps from the hanging hand can settle a part-turn short, palm
matched to the back of the hand, the fingers then bent to make up. So when the
forearms join the fit, and again when the fingers do, a grid of the forearm's pronation and the wrist's
flexion and deviation about the current angles is tried for both hands at once
(`Poser.pose_many`), and each hand keeps the combination whose skin lies
nearest the scan: the mean distance of its vertices to their nearest scan
points, each clipped at `register.CLIP` so that a far stray point does not decide.
"""

from __future__ import annotations

import itertools

import numpy as np
from scipy.spatial import cKDTree

from hitogata.fit.model import POSE_NAMES, BodyModel
from hitogata.fit.regions import REGIONS, vertex_regions
from hitogata.pose import Poser

# Offsets tried (degrees) about the current angles: a forearm's turn, a wrist's flexion and deviation.
GRID = {"forearm_{s}.pronation": (-60.0, -40.0, -20.0, 0.0, 20.0, 40.0, 60.0), "hand_{s}.flexion": (-30.0, 0.0, 30.0),
        "hand_{s}.radial_deviation": (-15.0, 0.0, 15.0)}
SIDES = {"l": "left hand", "r": "right hand"}


def search_hands(model: BodyModel, poser: Poser, pose: np.ndarray, points: np.ndarray, clip: float) -> np.ndarray:
    """The pose with each hand's turn (`GRID`) the best of the grid's for the scan points (P, 3), body frame."""
    lo, hi = model.pose_bounds
    combinations = list(itertools.product(*GRID.values()))
    candidates = np.repeat(pose[None], len(combinations), axis=0)
    for c, offsets in enumerate(combinations):
        for template, offset in zip(GRID, offsets):
            for side in SIDES:
                k = POSE_NAMES.index(template.format(s=side))
                candidates[c, k] = np.clip(pose[k] + np.radians(offset), lo[k], hi[k])
    rest = model.rest_complex(poser)
    surfaces = poser.pose_many(np.stack([model.angles(poser, p, rest) for p in candidates]))
    tree = cKDTree(points)
    regions = vertex_regions(poser.body)
    out = pose.copy()
    for side, region in SIDES.items():
        hand = np.flatnonzero(regions == REGIONS.index(region))
        distance, _ = tree.query(surfaces[:, hand].reshape(-1, 3))
        best = int(np.argmin(np.minimum(distance, clip).reshape(len(combinations), -1).mean(axis=1)))
        for template in GRID:
            k = POSE_NAMES.index(template.format(s=side))
            out[k] = candidates[best, k]
    return out
