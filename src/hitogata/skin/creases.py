"""The elastic skin's self-contact with its creases folded: one solve for a held pose and for a motion's frame.

The 40 mm tissue mesh bows out where the skin of a flexed joint should crease; the barrier's target is
therefore the elastic skin with its creases tied back towards skinning's fold (`contact.crease_tether`,
spread smoothly over the skin), the volume they give up swelling the free skin round them. The barrier
(`geometry.barrier_contact`) then takes the skin along a path of postures to that target; where the
result crosses skin the barrier does not hold apart it is held back (`contact.hold_back_crossings`),
and a crease whose skin still crosses is let go (its tether taken off, fading over the skin round it)
and the barrier solved again, at most `CreaseSettings.releases` times. `single_pose.elastic_pose` reaches its pose from
rest; `motion_contact.resolve_frames` reaches each frame from the last one's skin.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from hitogata.skin.contact import FOLDING, crease_tether, fold_angles, hold_back_crossings, skin_contact, skin_limiter
from hitogata.geometry.barrier_contact import BarrierResult, barrier_resolve
from hitogata.geometry.mesh_checks import enclosed_volume
from hitogata.skin.settings import SKIN_DEFAULTS, SkinSettings

if TYPE_CHECKING:
    from hitogata.dynamics.motion import BodyDynamics

@dataclass(frozen=True)
class CreaseSolve:
    """The barrier's result, the skin (V, 3), how far (m) each vertex was held back (V,), and the target
    the barrier was last given (V, 3: the elastic skin with its creases tied back)."""

    barrier: BarrierResult
    skin: np.ndarray
    held: np.ndarray
    target: np.ndarray


def _tethers(dynamics: BodyDynamics, plain: np.ndarray, rotations: np.ndarray, free: np.ndarray,
             settings: SkinSettings) -> np.ndarray:
    """(V,) the share of the elastic offset each vertex gives up (`contact.crease_tether` on the `free` skin of
    a posture skinned as `plain` (V, 3) by the parts' `rotations` (parts, 3, 3)), spread over the skin in steps
    of 1/`settings.creases.levels`."""
    creases = settings.creases
    folded = np.zeros(len(free))  # the creases lie on the free skin: the joints' folds there only
    folded[free] = fold_angles(dynamics.poser.skin.weights[free], rotations, creases.fold_weight)
    test = skin_contact(dynamics.poser, settings.penetration)
    tether = crease_tether(test.rest, plain, test.faces, folded, free, creases)
    return skin_limiter(dynamics, settings).spread(np.round(tether * creases.levels) / creases.levels)


def solve_creased(dynamics: BodyDynamics, before: Sequence[np.ndarray], plain: np.ndarray, offset: np.ndarray,
                  rotations: np.ndarray, free: np.ndarray, hold_towards: np.ndarray | None = None,
                  settings: SkinSettings = SKIN_DEFAULTS) -> CreaseSolve:
    """The skin `plain + offset` ((V, 3) skinned by the parts' `rotations` (parts, 3, 3), and its elastic offset)
    with its self-contact resolved, reached along `before` (the path's postures before the target, the first
    free of crossings), its creases on the barrier's free skin tied back (`free`: (steps, V) bool, each step's
    unknowns, `barrier_contact.contact_regions`; the last row all of them); held back towards
    `hold_towards` (a skin free of crossings; None: the last step's start) where it crosses skin the barrier
    does not hold apart; with the constants of `settings`."""
    test, limiter = skin_contact(dynamics.poser, settings.penetration), skin_limiter(dynamics, settings)
    releases = settings.creases.releases
    elastic = np.asarray(plain + offset, dtype=float)
    tether = _tethers(dynamics, plain, rotations, free[-1], settings)
    path = list(before)
    earlier: list[int] = []  # the iterations of the path's steps that a solve again resumes after
    for release in range(releases + 1):
        target = elastic - tether[:, None] * offset
        swell = enclosed_volume(elastic, test.faces) - enclosed_volume(target, test.faces) if tether.any() else 0.0
        resolved = barrier_resolve([*path, target], test, settings.barrier, folding=FOLDING, swell=swell,
                                   free=free[-len(path):], resumed=release > 0)
        # the steps before the last hang on the path alone, not on the target: a solve again starts where the
        # last step started (the same skin, so the same result), and reports the path's iterations as one solve
        resolved = replace(resolved, iterations=earlier + resolved.iterations)
        path, earlier = [resolved.before_last], resolved.iterations[:-1]
        start = resolved.before_last if hold_towards is None else hold_towards
        skin, held = hold_back_crossings(dynamics, resolved.vertices, start, settings)
        if release == releases or not tether.any():
            break
        let_go = _creases_at(limiter.graph, tether, np.unique(test.faces[limiter.crossings(skin, tether > 0)]))
        if not let_go.any():  # nothing crosses where a crease is tethered
            break
        tether = tether * (1.0 - limiter.spread(let_go.astype(float)))
    return CreaseSolve(resolved, skin, held, target)


def _creases_at(graph: sp.csr_matrix, tether: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """(V,) bool: the creases (pieces of the skin's edge `graph` where `tether` > 0) holding any of `vertices`."""
    inside = np.flatnonzero(tether > 0.0)
    _, piece = connected_components(graph[inside][:, inside], directed=False)
    hit = np.isin(inside, vertices)
    out = np.zeros(len(tether), dtype=bool)
    out[inside[np.isin(piece, piece[hit])]] = True
    return out
