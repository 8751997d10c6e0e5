"""Postures for the measurement tests, made by the real posing code (`hitogata.posing.pose`).

Each returns the skin vertices and the 163 rig joint centres of the posture,
the two arrays the measurement functions take.
"""

from __future__ import annotations

import numpy as np

from hitogata.body import Body
from hitogata.posing import pose_body


def posture(body: Body, clinical: dict[str, float]) -> tuple[np.ndarray, np.ndarray]:
    """Vertices and rig joint centres with the given clinical angles (radians), LBS skinning."""
    posed = pose_body(body, clinical=clinical)
    return posed.vertices, posed.rig_joints


def flex_elbow(body: Body, flexion: float, side: str = "R") -> tuple[np.ndarray, np.ndarray]:
    """The elbow flexed to `flexion` radians (0 = straight arm)."""
    return posture(body, {f"forearm_{side.lower()}.flexion": flexion})


def flex_hip(body: Body, flexion: float, side: str = "R") -> tuple[np.ndarray, np.ndarray]:
    """The thigh raised forwards to `flexion` radians of hip flexion."""
    return posture(body, {f"thigh_{side.lower()}.flexion": flexion})
