"""The skeleton as a picture (the paper's Fig. 3(a)): bones, joints, muscles, translucent skin.

Each part is a capsule from its joint centre to its tail; a part whose joint
does not sit on its parent's tail (a hip on the pelvis, a clavicle on the
spine, a finger on the hand) is tied to its parent's joint by a capsule too,
so the figure reads as one skeleton. Joints are spheres. Muscles are straight
lines from origin to insertion (the paper's model; rotation muscles' helices
are drawn as their chords): the named ones bold, the others, if asked for,
thin and faded.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from hitogata.errors import HitogataError
from hitogata.posing.pose import PosedBody
from hitogata.render.scene import Item, Layer, Lines, Points

BONE = "#f1ead9"
JOINT = "#2c3e50"
MUSCLE = "#c0392b"
MUSCLE_FADED = "#e6a8a0"
SKIN = "#e9b99a"
SKIN_OPACITY = 0.3
BONE_RADIUS = (0.0035, 0.010)  # m: fingers … long bones
BONE_SLENDERNESS = 0.045  # radius / length, within BONE_RADIUS
SPINE_RADIUS = 0.008  # the parts sharing the spine's weights: pelvis, vertebrae, head
JOINT_SCALE = 1.35  # joint sphere radius / its part's bone radius
MUSCLE_RADIUS = (0.0015, 0.003)  # m: other muscles, highlighted ones
TIED = 1e-3  # m: a joint this near its parent's tail needs no tie


def bone_radii(posed: PosedBody) -> np.ndarray:
    """(N,) capsule radius per part: slender for small parts, a fixed column for the spine."""
    sk = posed.skeleton
    radii = np.clip(BONE_SLENDERNESS * sk.lengths, *BONE_RADIUS)
    spine = {name for shared in sk.spec.shared for name in shared.parts}
    radii[[sk.index(name) for name in spine]] = SPINE_RADIUS
    return radii


def bone_segments(posed: PosedBody) -> tuple[np.ndarray, np.ndarray]:
    """(S, 2, 3) posed bone capsules (each part, then the ties to parents) and their radii."""
    sk = posed.skeleton
    joints, tails = posed.pose.joints[0], posed.pose.tails[0]
    radii = bone_radii(posed)
    child = np.flatnonzero(sk.parents >= 0)
    parent = sk.parents[child]
    loose = np.linalg.norm(sk.joints[child] - sk.tails[parent], axis=1) > TIED
    child, parent = child[loose], parent[loose]
    segments = np.concatenate([np.stack([joints, tails], axis=1), np.stack([joints[parent], joints[child]], axis=1)])
    return segments, np.concatenate([radii, np.minimum(radii[child], radii[parent])])


def skeleton_items(
    posed: PosedBody, *, skin: bool = False, muscles: Iterable[str] = (), other_muscles: bool = False
) -> list[Item]:
    """Render items for a posed skeleton: the named `muscles` bold, optionally the others and the skin."""
    segments, radii = bone_segments(posed)
    items: list[Item] = [
        Lines(segments, color=BONE, radius=radii),
        Points(posed.joints, color=JOINT, radius=JOINT_SCALE * bone_radii(posed)),
    ]
    named = list(muscles)
    unknown = sorted(set(named) - set(posed.muscle_names))
    if unknown:
        raise HitogataError(f"muscle {unknown[0]!r}: not in this body's muscle list")
    lines = posed.muscle_lines
    marked = np.isin(posed.muscle_names, named)
    if other_muscles and (~marked).any():
        items.append(Lines(lines[~marked], color=MUSCLE_FADED, radius=MUSCLE_RADIUS[0]))
    if marked.any():
        items.append(Lines(lines[marked], color=MUSCLE, radius=MUSCLE_RADIUS[1]))
    if skin:
        items.append(Layer(posed.vertices, posed.faces, color=SKIN, opacity=SKIN_OPACITY, backfaces=False))
    return items
