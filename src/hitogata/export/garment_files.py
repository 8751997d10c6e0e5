"""A dressed garment's files: the levels' table, the skin's pressure map, the garment's rings, a GLB, a picture.

Tables are CSV at the user's units (mmHg and Pa, cm, %); the GLB holds the body's skin and the garment's
mesh as solved (metres, glTF's convention); the picture is the pressure map (mmHg) on the skin under the
garment with the garment's outline, front, right side and back.
"""

from __future__ import annotations

import csv
import math
import io
from pathlib import Path

import numpy as np

from hitogata.export.atomic import write_bytes_atomically
from hitogata.garment.contact.answers import GarmentContact
from hitogata.garment.contact.motion import MotionContact
from hitogata.garment.pressure import MMHG

SKIN_RGBA = (0.85, 0.71, 0.61, 1.0)
GARMENT_RGBA = (0.15, 0.25, 0.45, 0.85)


def _csv(rows: list[dict[str, float | str]]) -> bytes:
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=list(rows[0]), lineterminator="\n")
    writer.writeheader()
    for row in rows:
        # a figure without meaning (Laplace's at a level it has no formula for, the rigid body's indentation)
        # is left empty, never written as a number
        writer.writerow({k: (("" if not math.isfinite(v) else f"{v:.4g}") if isinstance(v, float) else v)
                         for k, v in row.items()})
    return out.getvalue().encode("utf-8")


def levels_csv(result: GarmentContact) -> bytes:
    """One row per level: contact pressure (mmHg, Pa) and Laplace's (mmHg), girths, strains, the hold."""
    return _csv([level.as_row() for level in result.levels])


def skin_csv(result: GarmentContact) -> bytes:
    """One row per skin vertex under the garment: position (cm) and pressure (Pa, mmHg)."""
    rows: list[dict[str, float | str]] = []
    for k in np.flatnonzero(result.under):
        x, y, z = 100 * result.skin[k]
        p = float(result.pressure[k])
        rows.append({"vertex": str(int(k)), "x_cm": float(x), "y_cm": float(y), "z_cm": float(z),
                     "pressure_Pa": p, "pressure_mmHg": p / MMHG})
    return _csv(rows)


def garment_csv(result: GarmentContact) -> bytes:
    """One row per garment face: its course and wale strain (%)."""
    return _csv([{"face": str(f), "course_strain_pct": float(100 * c), "wale_strain_pct": float(100 * w)}
                 for f, (c, w) in enumerate(zip(result.course_strain, result.wale_strain))])


def dressed_glb(result: GarmentContact) -> bytes:
    """The body's skin and the garment's mesh, two plain meshes."""
    from hitogata.export.gltf import GlbBuilder, add_mesh

    builder = GlbBuilder()
    add_mesh(builder, result.skin, result.faces, "body", SKIN_RGBA)
    add_mesh(builder, result.garment, result.garment_faces, "garment", GARMENT_RGBA, double_sided=True)
    return builder.to_bytes()


def pressure_picture(result: GarmentContact) -> bytes:
    """The pressure map (mmHg) on the skin under the garment, front, right side and back."""
    from hitogata.render import Layer, png_bytes, render_views, side_by_side, titled

    mmhg = result.pressure / MMHG
    covered = result.under[result.faces].all(axis=1)
    top = max(float(np.percentile(mmhg[result.under], 98)) if result.under.any() else 1.0, 1e-3)
    items = [Layer(result.skin, result.faces[covered], scalars=mmhg, colormap="viridis", clim=(0.0, top),
                   scalar_title="pressure (mmHg)"),
             Layer(result.skin, result.faces[~covered], color="#d9b59c")]
    views = render_views(items, views=("front", "right", "back"), size=(None, 560))
    return png_bytes(titled(side_by_side(views), f"{result.title}: contact pressure on the skin"))


def motion_csv(motions: dict[str, MotionContact]) -> bytes:
    """One row per motion, sampled frame and level: the contact pressure (mmHg; the sensor-sized peak too),
    the indentation (mm; empty on the rigid body), the course strain and whether the frame's solve started
    from the last frame's ("warm") or from outside the body ("cold")."""
    rows: list[dict[str, float | str]] = []
    for name, motion in motions.items():
        for frame, (time, result, warm) in enumerate(zip(motion.times, motion.frames, motion.warm)):
            for level in result.levels:
                row = level.as_row()
                rows.append({"motion": name, "frame": str(frame), "time_s": float(time), "level": level.level,
                             "pressure_mmHg": row["pressure_mmHg"], "peak_mmHg": row["peak_mmHg"],
                             "indentation_mm": row["indentation_mm"], "deepest_mm": row["deepest_mm"],
                             "course_strain_pct": row["course_strain_pct"], "start": "warm" if warm else "cold"})
    return _csv(rows)


def write_dressing(folder: Path, result: GarmentContact, motions: dict[str, MotionContact] | None = None) -> list[str]:
    """Every file of a dressed garment into `folder` (with `motions`, its answers through them:
    pressure_motion.csv); their names."""
    files = {"pressure.csv": levels_csv(result), "skin_pressure.csv": skin_csv(result),
             "garment_strain.csv": garment_csv(result), "dressed.glb": dressed_glb(result),
             "pressure.png": pressure_picture(result)}
    if motions:
        files["pressure_motion.csv"] = motion_csv(motions)
    for name, data in files.items():
        write_bytes_atomically(folder / name, data)
    return list(files)
