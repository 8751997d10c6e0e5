"""What `hitogata body … --measure` prints and writes: a table, JSON, CSV and pictures.

`measure_report` measures a body at rest or in a posture and writes, into an
existing directory, every file atomically (`export.atomic`):

- `measurements.json`: values in metres and centimetres, the landmark vertex
  indices, and for a posture the strain figures of each zone;
- `measurements.csv`: one row per measurement, in cm;
- `measurements.png`: the body from the front, the right side and the back with
  every tape drawn where it lies;
- for a posture only: `strain_zones.csv` and `strain.png` (heat map of the
  largest principal strain, front and back), on the fine skin when its posed
  vertices are given (`hitogata.skin.fine_skin`), else on the skin.
"""

from __future__ import annotations

import json
import os
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from hitogata.body.model import Body
from hitogata.errors import HitogataError
from hitogata.export.atomic import write_bytes_atomically
from hitogata.measure.landmarks import body_landmarks, landmark_positions
from hitogata.measure.measurements import Measurements, measure, measure_with_paths, posture_arrays, undefined_because
from hitogata.measure.strain import skin_strain
from hitogata.measure.zones import ZoneStrain, zone_strains
from hitogata.report.heatmap import strain_heatmap
from hitogata.report.surface import render_png
from hitogata.skin.fine_skin import body_fine_skin

LABELS = {
    "stature": "stature",
    "neck_girth": "neck girth",
    "chest_girth": "chest (bust) girth",
    "underbust_girth": "underbust girth",
    "waist_girth": "waist girth",
    "omphalion_waist_girth": "waist girth at the navel",
    "iliac_crest_waist_girth": "iliac crest waist girth",
    "hip_girth": "hip girth",
    "thigh_girth": "thigh girth",
    "upper_arm_girth": "upper-arm girth",
    "armscye_girth": "armscye girth",
    "knee_girth": "knee girth",
    "calf_girth": "calf girth",
    "ankle_girth": "ankle girth (minimum)",
    "wrist_girth": "wrist girth",
    "back_waist_length": "back waist length",
    "across_back_width": "across-back width",
    "across_front_width": "across-front width",
    "shoulder_width": "shoulder width",
    "shoulder_length": "shoulder length",
    "arm_length": "arm length",
    "waist_to_hip_length": "waist to hip length",
    "crotch_length": "crotch length",
    "front_rise": "front rise",
    "back_rise": "back rise",
    "iliocristale_height": "iliac crest height",
    "inside_leg": "inside leg (crotch height)",
}


def measurement_table(measurements: Measurements, reference: Measurements | None = None) -> str:
    """A plain-text table in cm; with `reference` (e.g. the rest pose) also the change."""
    width = max(len(label) for label in LABELS.values())
    head = f"{'measurement':<{width}}  {'cm':>7}" + (f"  {'rest cm':>7}  {'change':>7}" if reference else "")
    lines = [head, "-" * len(head)]
    for name, value in measurements.as_dict().items():
        line = f"{LABELS[name]:<{width}}  {_cm(value):>7}"
        if reference is not None:
            before = reference.get(name)
            line += f"  {_cm(before):>7}  {_cm(value - before, signed=True):>7}"
        lines.append(line)
    return "\n".join(lines)


def _cm(metres: float, signed: bool = False) -> str:
    if not np.isfinite(metres):
        return "undefined"
    return f"{metres * 100:+.1f}" if signed else f"{metres * 100:.1f}"


@dataclass(frozen=True)
class MeasureReport:
    """What `measure_report` wrote (paths by kind) and measured (at rest: `rest` is None)."""

    files: dict[str, Path]
    measurements: Measurements
    rest: Measurements | None


def measure_report(
    body: Body,
    out_dir: str | os.PathLike,
    vertices: np.ndarray | None = None,
    joints: np.ndarray | None = None,
    title: str = "",
    fine_vertices: np.ndarray | None = None,
) -> MeasureReport:
    """Measure `body` (at rest, or posed by `vertices` and `joints`) and write the report files;
    skin strain on the fine skin posed as `fine_vertices` when given.

    Returns the written paths by kind and the measurements. `out_dir` must exist.
    """
    out = Path(out_dir)
    if not out.is_dir():
        raise HitogataError(f"{out}: not a directory; allowed an existing directory for the measurement report")
    posed = vertices is not None or joints is not None
    v, _ = posture_arrays(body, vertices, joints)
    heads = body.rig.heads if joints is None else joints
    values, paths = measure_with_paths(body, v, heads)  # name → polyline: the picture labels each tape
    written = {
        "json": out / "measurements.json",
        "csv": out / "measurements.csv",
        "picture": out / "measurements.png",
    }
    document: dict = {
        "units": "m",
        "measurements": _json_values(values),
        "measurements_cm": {k: None if x is None else round(x * 100, 2) for k, x in _json_values(values).items()},
        "undefined": {k: undefined_because(k) for k, x in _json_values(values).items() if x is None},
        "landmarks_m": {k: p.tolist() for k, p in landmark_positions(body_landmarks(body), v).items()},
    }
    picture = render_png(v, body.faces, ("front", "right", "back"), title=title, overlays=paths)  # tapes on the right
    rest = None
    if posed:
        rest = measure(body)
        fine = body_fine_skin(body)
        surface = (v, body.faces) if fine_vertices is None else (fine_vertices, fine.faces)
        strain = skin_strain(body.vertices if fine_vertices is None else fine.vertices, *surface)
        zones = zone_strains(body, strain)
        document["rest_measurements"] = _json_values(rest)
        document["zone_strain_percent"] = {name: asdict(z) for name, z in zones.items()}
        written["zones"] = out / "strain_zones.csv"
        written["strain"] = out / "strain.png"
        write_bytes_atomically(written["zones"], _zones_csv(zones).encode())
        write_bytes_atomically(written["strain"], strain_heatmap(*surface, strain, title=title))
    write_bytes_atomically(written["json"], (json.dumps(document, indent=2, allow_nan=False) + "\n").encode())
    write_bytes_atomically(written["csv"], _measurements_csv(values).encode())
    write_bytes_atomically(written["picture"], picture)
    return MeasureReport(written, values, rest)


def _json_values(values: Measurements) -> dict[str, float | None]:
    """Measurements for JSON: metres, null where not measurable (JSON has no NaN)."""
    return {k: (x if np.isfinite(x) else None) for k, x in values.as_dict().items()}


def _measurements_csv(values: Measurements) -> str:
    rows = ["measurement,value_cm"] + [f"{name},{x * 100:.2f}" if np.isfinite(x) else f"{name},undefined"
                                       for name, x in values.as_dict().items()]
    return "\n".join(rows) + "\n"


def _zones_csv(zones: dict[str, ZoneStrain]) -> str:
    columns = list(asdict(next(iter(zones.values()))))
    rows = ["zone," + ",".join(f"{c}_pct" for c in columns)]
    rows += [f"{name}," + ",".join(f"{getattr(z, c):.3f}" for c in columns) for name, z in zones.items()]
    return "\n".join(rows) + "\n"
