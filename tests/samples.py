"""Small inputs that test modules of several packages share."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import trimesh

# A two-joint BVH of two frames: the reader's good case, which the bad-input tests spoil one entry at a time.
SMALL_BVH = """HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Spine
  {
    OFFSET 0 10 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 0 10 0
    }
  }
}
MOTION
Frames: 2
Frame Time: 0.04
0 90 0 0 0 0 0 0 0
0 90 0 0 0 0 0 10 0
"""


def two_spheres(radius: float, subdivisions: int) -> tuple[Callable[[float], np.ndarray], np.ndarray, np.ndarray]:
    """Two icospheres as one surface of two contact groups: `apart(d)`, the vertices with the second sphere's
    centre d (m) above the first's; the faces; each vertex's group (0, 1)."""
    sphere = trimesh.creation.icosphere(subdivisions=subdivisions, radius=radius)
    v, f = np.asarray(sphere.vertices), np.asarray(sphere.faces)

    def apart(d: float) -> np.ndarray:
        return np.concatenate([v, v + [0.0, 0.0, d]])

    return apart, np.concatenate([f, f + len(v)]), np.repeat([0, 1], len(v))
