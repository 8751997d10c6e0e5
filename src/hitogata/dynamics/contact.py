"""The body's skin split into contact groups, for its self-contact test (`hitogata.geometry.contact`).

A contact group is a set of skeleton parts whose skin is held in shape by
its bones (an upper arm, a forearm, a thigh, the chest): it never meets
itself, and meets every other group. The groups part at every joint where
a garment's crease forms: elbow (upper arm | forearm), knee (thigh |
shank), hip (pelvis, abdomen | thigh), armpit (upper arm | shoulder, chest),
neck (head | neck | chest), the trunk folding (chest | abdomen | pelvis), and
the two legs. A skin vertex belongs to the group holding most of its
skinning weight.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from hitogata.geometry.contact import SelfContact

if TYPE_CHECKING:
    from hitogata.dynamics.motion import BodyDynamics
    from hitogata.options import Skinning
    from hitogata.pose import Poser

# Each group: the part-name prefixes it holds (a sided group takes parts of its own side only).
GROUPS: dict[str, tuple[str, ...]] = {
    "head": ("head", "jaw"),
    "neck": ("cervical_",),
    "chest": tuple(f"thoracic_{i}" for i in range(1, 9)),
    "abdomen": tuple(f"thoracic_{i}" for i in range(9, 13)) + ("lumbar_1", "lumbar_2", "lumbar_3"),
    "pelvis": ("lumbar_4", "lumbar_5", "pelvis"),
    **{f"{limb}_{side}": parts
       for side in "lr"
       for limb, parts in {
           "shoulder": (f"clavicle_{side}", f"scapula_{side}"),
           "upper_arm": (f"upper_arm_{side}",),
           "forearm": (f"forearm_{side}",),
           "hand": (f"hand_{side}", "thumb_", "index_", "middle_", "ring_", "little_"),
           "thigh": (f"thigh_{side}",),
           "shank": (f"shank_{side}",),
           "foot": (f"foot_{side}", f"toes_{side}"),
       }.items()},
}
# groups whose skin may fold onto itself (a crease: skin far apart at rest meets); a hand's, a foot's and
# the head's small triangles lie close everywhere and stay held in shape by their bones
FOLDING = tuple(g for g, name in enumerate(GROUPS) if not name.startswith(("hand", "foot", "head")))
APPROACH_STEPS = 4  # skinned postures on the barrier's path from rest to a posture


def part_groups(names: tuple[str, ...]) -> np.ndarray:
    """(parts,) the contact group of each skeleton part (index into GROUPS): the first group with a
    prefix of its name, on its side (a part named …_l belongs to a group named …_l).

    >>> part_groups(("pelvis", "forearm_l", "index_distal_r")).tolist()
    [4, 7, 15]
    """
    out = np.full(len(names), -1)
    for k, name in enumerate(names):
        side = name[-2:] if name.endswith(("_l", "_r")) else ""
        for g, (group, prefixes) in enumerate(GROUPS.items()):
            if name.startswith(prefixes) and (not side or group.endswith(side)):
                out[k] = g
                break
    missing = [n for n, g in zip(names, out) if g < 0]
    if missing:
        raise ValueError(f"skeleton parts without a contact group: {', '.join(missing)}")
    return out


def vertex_groups(weights: sp.csr_matrix, names: tuple[str, ...]) -> np.ndarray:
    """(V,) each skin vertex's contact group: the group holding most of its skinning weight."""
    groups = part_groups(names)
    onto = sp.csr_matrix((np.ones(len(names)), (np.arange(len(names)), groups)), shape=(len(names), len(GROUPS)))
    return np.asarray((weights @ onto).argmax(axis=1)).ravel()


def skin_contact(poser: Poser) -> SelfContact:
    """The self-contact test of a poser's body skin."""
    body = poser.body
    return SelfContact(body.vertices, body.faces, vertex_groups(poser.skin.weights, poser.skeleton.names))


def approach(poser: Poser, angles: np.ndarray, skinning: Skinning, root: np.ndarray | None = None
             ) -> list[np.ndarray]:
    """A path from the rest skin to a posture for the contact barrier (`geometry.barrier_contact`): the
    rest skin (free of crossings), then the skin skinned at APPROACH_STEPS even fractions of the joint
    angles (D,) (`root`: the whole body's (4, 4) transform, at every fraction), each step short enough
    for the barrier's continuous collision detection to follow."""
    fractions = np.arange(1, APPROACH_STEPS + 1)[:, None] / APPROACH_STEPS
    return [poser.body.vertices, *poser.pose_many(fractions * angles, skinning, root)]


def hold_back_crossings(dynamics: BodyDynamics, skin: np.ndarray, start: np.ndarray
                        ) -> tuple[np.ndarray, np.ndarray]:
    """The barrier's `skin` (V, 3) held back towards `start` (V, 3, a skin free of crossings beyond the rest
    body's: the last step's start, or a motion's previous frame) where it crosses skin the barrier does not
    hold apart (skin of one group near at rest: a breast's fold as the arm rises, the elbow crease's sides;
    skin not free), and how far (m) each vertex was held back (V,). Only crossings: a fold held back towards
    a start that crosses nearby would bring that crossing back."""
    step = skin - start
    held, kept = dynamics.skin_limiter(start, step, folds=False)
    return held, (1.0 - kept) * np.linalg.norm(step, axis=1)
