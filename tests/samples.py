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


# The short garment of the motion tests: ankle to calf, 32 vertices round, on the soft leg.
SHORT_GARMENT = '''title = "Ankle sleeve"
segment = "leg"
ease = "-20%"
levels = ["ankle", "calf"]
per_ring = 32
[fabric]
course = "400N/m"
wale = "200N/m"
'''

# The soft thick-walled cylinder (m) the garment contact is verified on (`garment.contact.verify`).
INNER, OUTER, LENGTH = 0.03, 0.05, 0.004


def soft_cylinder(youngs: float = 20e3, poisson: float = 0.49):
    """The soft cylinder (6 layers, 96 round, 1 long) under a linear ring of 300 N/m at 85 % of its girth on 5
    stations, started 2 mm out: (body, stations, tube, start)."""
    from hitogata.garment.contact.tube import build_tube
    from hitogata.garment.contact.verify import elliptic_rings, soft_annulus, straight_stations
    from hitogata.garment.fabric import Fabric

    body = soft_annulus(INNER, OUTER, LENGTH, youngs, poisson, 6, 96, 1)
    stations = straight_stations(LENGTH, 5)
    tube = build_tube(stations, 96, np.full(5, 0.85 * 2 * np.pi * OUTER), Fabric.linear(300.0), Fabric.linear(300.0),
                      30.0)
    return body, stations, tube, elliptic_rings(stations, OUTER + 0.002, OUTER + 0.002, 96)
