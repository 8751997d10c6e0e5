"""Levels a girth or width is taken at, found once on a body's rest surface.

ISO 8559-1 places some girths at an extreme rather than at a bone point: the
calf girth where the calf is largest, the ankle girth where the leg is
thinnest above the malleoli. Those levels are fractions along the limb (knee
to ankle joint centre), found by sampling the girth ⊥ the limb and refining
the best sample with a parabola through its neighbours, so that the level
varies continuously with the shape.
"""

from __future__ import annotations

import numpy as np

from hitogata.measure.axes import unit
from hitogata.measure.sections import tape_girth
from hitogata.geometry.topology import Topology

LEVEL_SAMPLES = 17  # girths sampled along a limb's span
CALF_SPAN = (0.15, 0.55)  # fractions of knee → ankle joint searched for the largest girth
ANKLE_SPAN = (0.60, 0.92)  # … and for the smallest, above the malleoli


def extreme_girth_level(v: np.ndarray, topo: Topology, start: np.ndarray, end: np.ndarray,
                        span: tuple[float, float], largest: bool) -> float:
    """The fraction along start → end (joint centres) where the girth ⊥ that line is largest
    (or smallest) within `span`."""
    axis = end - start
    normal = unit(axis)
    fractions = np.linspace(span[0], span[1], LEVEL_SAMPLES)
    girths = np.array([tape_girth(v, topo, start + f * axis, normal, start + f * axis).girth for f in fractions])
    score = girths if largest else -girths
    k = int(np.clip(np.nanargmax(score), 1, len(fractions) - 2))
    a, b, c = score[k - 1:k + 2]
    curvature = a - 2.0 * b + c
    shift = 0.0 if curvature >= 0.0 or not np.isfinite(curvature) else 0.5 * (a - c) / curvature
    return float(fractions[k] + np.clip(shift, -1.0, 1.0) * (fractions[1] - fractions[0]))

