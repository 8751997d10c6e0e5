"""Skin-strain colours: the largest principal strain per triangle, averaged to the vertices.

`hitogata.measure.skin_strain` gives each triangle's principal stretches
between the rest and the shown surface; the viewer needs a colour per vertex,
so each vertex takes the rest-area-weighted mean of its triangles' largest
principal strain. A diverging map centred on 0 %: blue where the skin is
compressed, white unstrained, red stretched, saturating at ±`LIMIT_PERCENT`.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from matplotlib import colormaps

from hitogata.measure import skin_strain

LIMIT_PERCENT = 30.0
COLOUR_MAP = "RdBu_r"


class StrainColouring:
    """Prepared once per body: the vertex-from-triangle averaging and the colour table."""

    def __init__(self, rest: np.ndarray, faces: np.ndarray) -> None:
        self.rest, self.faces = rest, faces
        tri = rest[faces]
        area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
        rows = faces.ravel()
        cols = np.repeat(np.arange(len(faces)), 3)
        incidence = sp.csr_matrix((np.repeat(area, 3), (rows, cols)), shape=(len(rest), len(faces)))
        total = np.asarray(incidence.sum(axis=1)).ravel()
        self.average = sp.diags(1.0 / np.maximum(total, 1e-30)) @ incidence
        self.table = (colormaps[COLOUR_MAP](np.linspace(0.0, 1.0, 256))[:, :3] * 255).astype(np.uint8)

    def vertex_strain(self, vertices: np.ndarray) -> np.ndarray:
        """(V,) largest principal strain, percent, per vertex."""
        per_face = np.nan_to_num(skin_strain(self.rest, vertices, self.faces).strain_max_percent)
        return self.average @ per_face

    def colours(self, vertices: np.ndarray) -> np.ndarray:
        """(V, 3) uint8 colours of the strain of `vertices` against the rest surface."""
        scaled = (np.clip(self.vertex_strain(vertices) / LIMIT_PERCENT, -1.0, 1.0) + 1.0) * 0.5
        return self.table[np.rint(scaled * 255).astype(np.int64)]


def legend() -> str:
    """One line of markdown saying what the colours mean."""
    return (
        f"Skin strain (largest principal, vs rest): blue −{LIMIT_PERCENT:.0f} % · white 0 · "
        f"red +{LIMIT_PERCENT:.0f} % or more"
    )
