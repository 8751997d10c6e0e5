"""The rig's joint centres in a posture given by per-part rigid transforms.

`measure` locates its planes with the MakeHuman rig's joint centres (bone
heads). A posing code that moves a different set of parts (the 65-part
skeleton) gives each part a skinning transform x ↦ R x + t; every rig joint
centre then follows the part whose rest joint centre is nearest to it. Where
the two coincide (shoulder, elbow, hip, knee, neck joints) the result is exact,
since a joint centre moves alike with both parts that meet there; rig joints
between vertebrae follow their nearest vertebra.
"""

from __future__ import annotations

import numpy as np


def carrying_parts(rest_heads: np.ndarray, part_joints: np.ndarray) -> np.ndarray:
    """(B,) for each rig joint centre (B, 3), the part whose rest joint centre (N, 3) is nearest."""
    rest_heads = np.asarray(rest_heads, dtype=np.float64)
    part_joints = np.asarray(part_joints, dtype=np.float64)
    return np.argmin(np.linalg.norm(rest_heads[:, None, :] - part_joints[None, :, :], axis=2), axis=1)


def carried_heads(
    rest_heads: np.ndarray, parts: np.ndarray, rotations: np.ndarray, translations: np.ndarray
) -> np.ndarray:
    """(..., B, 3) rig joint centres moved by their carrying parts' (`carrying_parts`) transforms,
    rotations (..., N, 3, 3) and translations (..., N, 3): one posture or a batch of them."""
    rotations, translations = np.asarray(rotations), np.asarray(translations)
    rest = np.asarray(rest_heads, dtype=np.float64)
    return np.einsum("...bij,bj->...bi", rotations[..., parts, :, :], rest) + translations[..., parts, :]


def posed_rig_heads(
    rest_heads: np.ndarray, part_joints: np.ndarray, rotations: np.ndarray, translations: np.ndarray
) -> np.ndarray:
    """(B, 3) posed rig joint centres from rest ones (B, 3), the parts' rest joint centres
    (N, 3) and their skinning rotations (N, 3, 3) and translations (N, 3)."""
    return carried_heads(rest_heads, carrying_parts(rest_heads, part_joints), rotations, translations)
