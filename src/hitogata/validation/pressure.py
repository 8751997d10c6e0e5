"""A pressure row answered two ways: Laplace's law on the rigid tape, and the contact garment on the soft body.

A row whose study gives its garment (`dataset.GarmentSpec`: an ease against the limb, or a relaxed
circumference at the level, and the fabric's modulus or tensile curve) is answered

- on the skinned surface by Laplace's law (`garment.pressure`): the fabric's tension at the strain the
  standing (or posed) tape girth makes, over the equivalent circle's radius — the quick estimate;
- on the elastic surface by the contact garment (`garment.contact`): a tube of the fabric along the
  row's segment (the leg from ankle to thigh, the trunk from hip to chest) at the row's ease, dressed on
  the standing body and solved with IPC contact; on a limb the tissue mesh under it takes its load
  (decision 0024), on the trunk the skin is held rigid (decision 0020). Its answer is the contact's mean
  pressure round the row's level.

The tube runs along the segment's levels from the lowest to the highest any row of that garment asks
for (one level more where they ask for one: a tube needs two), so that rows of one body with one
garment (the same ease or relaxed size and fabric) share one solve and no leg is dressed further than
the rows need. A relaxed circumference at one level is carried along the tube as the ease it makes at
that level (the garment's relaxed size elsewhere is not given). The contact is solved on the standing
body only: a row in another posture has Laplace's answer and an undefined contact.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hitogata.body import Body
from hitogata.elastic.materials import Materials
from hitogata.errors import HitogataError
from hitogata.garment.fabric import Fabric
from hitogata.validation.dataset import Dataset, Row

NO_FABRIC = "the study gives no fabric tension or no garment size: the pressure cannot be computed"


def row_fabric(row: Row) -> Fabric | None:
    """The pressure row's fabric, or None where the study gives no tension or no garment size."""
    spec = row.garment
    if spec is None or (spec.ease is None and spec.relaxed is None):
        return None
    if spec.curve is not None:
        return Fabric(tuple(p[0] for p in spec.curve), tuple(p[1] for p in spec.curve), "the study's curve")
    if spec.modulus is not None:
        return Fabric.linear(spec.modulus)
    return None


def laplace_level(row: Row, body: Body, skin: np.ndarray, joints: np.ndarray):
    """Laplace's answer at the row's level (`garment.pressure.LevelPressure`) on the skin given."""
    from hitogata.garment.pressure import Garment, garment_pressure

    spec, fabric = row.garment, row_fabric(row)
    if spec is None or fabric is None:
        raise ValueError(f"row {row.id!r}: {NO_FABRIC}")
    garment = (Garment(ease=spec.ease, levels=(row.quantity,)) if spec.ease is not None
               else Garment(relaxed={row.quantity: float(spec.relaxed or 0.0)}))
    return garment_pressure(body, garment, fabric, skin, joints)[row.quantity]


@dataclass(frozen=True)
class ContactGarment:
    """The contact garment of a row: the segment it covers, its ease there and its fabric (the cache key of
    its solve, with the body)."""

    segment: str
    levels: tuple[str, ...]
    ease: float
    fabric: Fabric


def covered_levels(dataset: Dataset) -> dict[str, tuple[str, ...]]:
    """By pressure row id: the levels its garment's tube covers (see the module note)."""
    from hitogata.garment.contact.spec import SEGMENTS

    wanted: dict[tuple, set[str]] = {}
    for row in dataset.rows:
        if row.kind == "pressure" and row_fabric(row) is not None:
            wanted.setdefault((dataset.source_of(row).subjects, row.garment), set()).add(row.quantity)
    out = {}
    for row in dataset.rows:
        if row.kind == "pressure" and row_fabric(row) is not None:
            order = next(levels for levels in SEGMENTS.values() if row.quantity in levels)
            at = sorted(order.index(level) for level in wanted[(dataset.source_of(row).subjects, row.garment)])
            low, high = at[0], at[-1]
            if low == high:
                low, high = (low, low + 1) if low + 1 < len(order) else (low - 1, low)
            out[row.id] = order[low:high + 1]
    return out


def contact_garment(row: Row, body: Body, levels: tuple[str, ...], where: str) -> ContactGarment:
    """The tube a row's garment becomes along `levels` (see the module note); `where` names the row."""
    from hitogata.garment.contact.spec import SEGMENTS

    spec, fabric = row.garment, row_fabric(row)
    if spec is None or fabric is None:
        raise ValueError(f"{where}: {NO_FABRIC}")
    segment = next(name for name, order in SEGMENTS.items() if row.quantity in order)
    if spec.ease is not None:
        return ContactGarment(segment, levels, float(spec.ease), fabric)
    standing = laplace_level(row, body, np.asarray(body.vertices, dtype=float), body.rig.heads)
    return ContactGarment(segment, levels, float(spec.relaxed or 0.0) / standing.girth - 1.0, fabric)


def dress_row_garment(body: Body, garment: ContactGarment, materials: Materials, where: str):
    """The contact garment on the standing body, solved (`garment.contact.GarmentContact`): soft on a limb."""
    from hitogata.garment.contact import dress_garment
    from hitogata.garment.contact.spec import GarmentSpec

    spec = GarmentSpec(where, f"the garment of {where}", garment.segment, garment.levels, None, garment.ease,
                       garment.fabric, garment.fabric)
    return dress_garment(body, spec, soft=True, materials=materials)


def contact_pressure(result, level: str) -> float:
    """The contact's mean pressure (mmHg) round a level of a solved garment; refused (HitogataError) where the
    solve did not converge or its exact checks failed: such a figure is not an answer."""
    from hitogata.garment.pressure import MMHG

    if not result.converged:
        raise HitogataError("the contact solve did not converge")
    if result.inside or result.crossing:
        raise HitogataError(f"the garment ends inside the body ({result.inside} vertices inside, crossing "
                            f"{result.crossing})")
    found = [lv for lv in result.levels if lv.level == level]
    if not found or not np.isfinite(found[0].pressure):
        raise HitogataError(f"the garment has no contact at the {level}")
    return float(found[0].pressure / MMHG)
