"""What a user reads of a dressing at its levels, from the garment and the tissue as they stand.

At each level the mean pressure of the garment's rings within `BAND` of the level's plane (the skin's
push on them over their area: the mean round the girth that RAL-GZ 387/1 classifies a stocking by) and,
on the soft limb, the mean and largest indentation of the tissue's section nearest the level. The
answers (`answers`) report them; Newton (`equilibrium.settle`) watches them step by step and stops where
a step changes none of them by more than `PRINTED`: half the last digit `hitogata dress` and the fit
report print of a pressure (0.1 mmHg), the last digit they print of an indentation (0.01 mm). A pressure
sensor under a garment (PicoPress, Kikuhime) reads to about 1 mmHg, and measured interface pressures of
one garment scatter by 2–3 mmHg between studies: the tolerance is far inside both.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from hitogata.garment.contact.pressure import patch_pressure
from hitogata.garment.contact.tissue import LimbTissue
from hitogata.garment.contact.tube import Tube
from hitogata.garment.pressure import MMHG
from hitogata.geometry.normals import vertex_areas

BAND = 0.01  # m each side of a level's plane


@dataclass(frozen=True)
class ReadTolerance:
    """How much the read figures may change in a converged Newton step: the levels' pressures (Pa) and
    indentations (m, the mean and the largest round the level)."""

    pressure: float
    indentation: float


PRINTED = ReadTolerance(pressure=0.05 * MMHG, indentation=1e-5)


@dataclass(frozen=True, eq=False)
class LevelReader:
    """The levels' read figures of a garment on its tube (`read`): which garment vertices make each level's
    rings and, on the soft limb, its tissue section nearest the level."""

    tube: Tube
    rings: np.ndarray  # (L, V) bool: the garment vertices within BAND of each level's plane
    tissue: LimbTissue | None
    sections: np.ndarray  # (L,) the tissue's section nearest each level (empty: the rigid body)
    tolerance: ReadTolerance = field(default=PRINTED)

    @classmethod
    def build(cls, tube: Tube, arc: np.ndarray, level_arc: np.ndarray, tissue: LimbTissue | None,
              tolerance: ReadTolerance = PRINTED) -> LevelReader:
        """For a tube whose stations lie at arc lengths `arc` (M,) (m), its levels at `level_arc` (L,) (m)."""
        vertex_arc = np.asarray(arc)[np.arange(tube.n_rings * tube.per_ring) // tube.per_ring]
        rings = np.abs(vertex_arc[None, :] - np.asarray(level_arc)[:, None]) <= BAND
        sections = np.zeros(0, dtype=np.int64) if tissue is None else \
            np.argmin(np.abs(np.asarray(arc)[tissue.stations][None, :] - np.asarray(level_arc)[:, None]), axis=1)
        return cls(tube, rings, tissue, sections, tolerance)

    def pressures(self, garment: np.ndarray, garment_force: np.ndarray) -> np.ndarray:
        """(L,) Pa: each level's mean pressure from the skin's push `garment_force` (V, 3) on its rings."""
        pushed = np.linalg.norm(garment_force, axis=1)  # frictionless: along the skin's normal
        areas = vertex_areas(garment, self.tube.faces)
        return np.array([patch_pressure(pushed, areas, rings) for rings in self.rings])

    def indentations(self, nodes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(L,), (L,) m: the mean and the largest indentation of each level's tissue section, the tissue's
        nodes at `nodes`; NaN on the rigid body."""
        if self.tissue is None:
            undefined = np.full(len(self.rings), np.nan)
            return undefined, undefined
        moved_in = self.tissue.indentation(nodes)[self.sections]
        return moved_in.mean(axis=1), moved_in.max(axis=1)

    def read(self, garment: np.ndarray, nodes: np.ndarray, garment_force: np.ndarray) -> np.ndarray:
        """(3L,): the levels' pressures (Pa), mean and largest indentations (m), for `changed`."""
        return np.concatenate([self.pressures(garment, garment_force), *self.indentations(nodes)])

    def changed(self, before: np.ndarray, after: np.ndarray) -> bool:
        """Whether two readings (`read`) differ anywhere by more than the tolerance."""
        n = len(self.rings)
        limit = np.concatenate([np.full(n, self.tolerance.pressure), np.full(2 * n, self.tolerance.indentation)])
        difference = np.abs(after - before)
        defined = np.isfinite(difference)
        return bool(np.any(difference[defined] > limit[defined]))
