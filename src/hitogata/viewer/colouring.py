"""The skin's colour maps: skin strain, the garment zones' stretch, a stretch garment's pressure.

`hitogata.measure.skin_strain` gives each triangle's principal stretches
between the rest and the shown surface; the viewer needs a colour per vertex,
so each vertex takes the rest-area-weighted mean of its triangles' largest
principal strain. The maps (`SkinColours`, one per body and garment):

- skin strain: that strain everywhere, a diverging map centred on 0 %: blue
  where the skin is compressed, white unstrained, red stretched, saturating
  at ±`LIMIT_PERCENT`;
- zone stretch: the same strain on the garment zones' skin only
  (`garment.stretch`), on the fit report's scale (±`garment.stretch.MAP_RANGE`),
  the rest of the skin in its own colour;
- pressure (with a garment): the garment's pressure (`garment.pressure_map`,
  mmHg) on the skin it covers, 0 to `PRESSURE_LIMIT_MMHG` (saturating), the
  uncovered skin in its own colour.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from matplotlib import colormaps

from hitogata.body.model import Body
from hitogata.errors import HitogataError
from hitogata.garment.fabric import Fabric
from hitogata.garment.pressure import MMHG, Garment
from hitogata.garment.pressure_map import pressure_map
from hitogata.garment.stretch import MAP_RANGE
from hitogata.measure import skin_strain
from hitogata.garment.stretch import garment_zones
from hitogata.geometry.normals import triangle_areas

LIMIT_PERCENT = 30.0
COLOUR_MAP = "RdBu_r"
PRESSURE_COLOUR_MAP = "viridis"
PRESSURE_LIMIT_MMHG = 40.0  # the top of compression class III (RAL-GZ 387: 34–46 mmHg) lies within
SKIN_RGB = np.array([225, 190, 165], dtype=np.uint8)
MAPS = ("skin strain", "zone stretch", "pressure")


def _table(name: str) -> np.ndarray:
    return (colormaps[name](np.linspace(0.0, 1.0, 256))[:, :3] * 255).astype(np.uint8)


def _lookup(table: np.ndarray, values: np.ndarray, low: float, high: float) -> np.ndarray:
    """(V, 3) colours of values over [low, high] (saturating); NaN takes the skin's colour."""
    scaled = np.clip((np.nan_to_num(values) - low) / (high - low), 0.0, 1.0)
    out = table[np.rint(scaled * 255).astype(np.int64)]
    out[np.isnan(values)] = SKIN_RGB
    return out


class StrainColouring:
    """Prepared once per body: the vertex-from-triangle averaging and the colour table."""

    def __init__(self, rest: np.ndarray, faces: np.ndarray) -> None:
        self.rest, self.faces = rest, faces
        tri = rest[faces]
        area = triangle_areas(tri)
        rows = faces.ravel()
        cols = np.repeat(np.arange(len(faces)), 3)
        incidence = sp.csr_matrix((np.repeat(area, 3), (rows, cols)), shape=(len(rest), len(faces)))
        total = np.asarray(incidence.sum(axis=1)).ravel()
        self.average = sp.diags(1.0 / np.maximum(total, 1e-30)) @ incidence
        self.table = _table(COLOUR_MAP)

    def vertex_strain(self, vertices: np.ndarray) -> np.ndarray:
        """(V,) largest principal strain, percent, per vertex."""
        per_face = np.nan_to_num(skin_strain(self.rest, vertices, self.faces).strain_max_percent)
        return self.average @ per_face

    def colours(self, vertices: np.ndarray) -> np.ndarray:
        """(V, 3) uint8 colours of the strain of `vertices` against the rest surface."""
        return _lookup(self.table, self.vertex_strain(vertices), -LIMIT_PERCENT, LIMIT_PERCENT)


class SkinColours:
    """The colour maps of one body (and a stretch garment, if given); the zones are found on first use."""

    def __init__(self, body: Body, garment: tuple[Garment, Fabric] | None = None) -> None:
        self.body, self.garment = body, garment
        self.strain = StrainColouring(body.vertices, body.faces)
        self._in_zones: np.ndarray | None = None
        self._pressure_table = _table(PRESSURE_COLOUR_MAP)

    @property
    def maps(self) -> tuple[str, ...]:
        """The maps this body can show: pressure only with a garment."""
        return MAPS if self.garment is not None else MAPS[:2]

    def in_zones(self) -> np.ndarray:
        """(V,) the vertices of the garment zones' faces."""
        if self._in_zones is None:
            mask = np.zeros(len(self.body.vertices), bool)
            for faces in garment_zones(self.body)[0].values():
                mask[self.body.faces[faces].ravel()] = True
            self._in_zones = mask
        return self._in_zones

    def values(self, name: str, vertices: np.ndarray, rig_joints: np.ndarray) -> np.ndarray:
        """(V,) the map's quantity per vertex (% or mmHg), NaN where it does not apply."""
        if name not in self.maps:
            why = "" if name != "pressure" else " (pressure needs a garment: --garment-ease and --fabric)"
            raise HitogataError(f"colour map {name!r}{why}: allowed {', '.join(self.maps)}")
        if name == "pressure":
            assert self.garment is not None
            return pressure_map(self.body, *self.garment, vertices, rig_joints).pressure / MMHG
        strain = self.strain.vertex_strain(vertices)
        return strain if name == "skin strain" else np.where(self.in_zones(), strain, np.nan)

    def colours(self, name: str, vertices: np.ndarray, rig_joints: np.ndarray) -> np.ndarray:
        """(V, 3) uint8 colours of map `name` for the surface `vertices` (rig joint centres: `rig_joints`)."""
        values = self.values(name, vertices, rig_joints)
        if name == "pressure":
            return _lookup(self._pressure_table, values, 0.0, PRESSURE_LIMIT_MMHG)
        limit = LIMIT_PERCENT if name == "skin strain" else MAP_RANGE
        return _lookup(self.strain.table, values, -limit, limit)


def legend(name: str = "skin strain") -> str:
    """One line of markdown saying what the colours of map `name` mean."""
    if name == "pressure":
        return (f"Garment pressure (Laplace's law, mmHg): dark blue 0 · green · yellow {PRESSURE_LIMIT_MMHG:.0f} "
                "or more; uncovered skin in its own colour")
    if name == "zone stretch":
        return (f"Garment zones' stretch (largest principal, vs rest; the fit report's scale): blue −{MAP_RANGE:.0f} % "
                f"· white 0 · red +{MAP_RANGE:.0f} % or more; skin outside the zones in its own colour")
    return (f"Skin strain (largest principal, vs rest): blue −{LIMIT_PERCENT:.0f} % · white 0 · "
            f"red +{LIMIT_PERCENT:.0f} % or more")
