"""A study's answer: its rows read back, and percentile tables per size (or body cluster) and motion.

Per group and motion, for each girth and length: P5, P50 and P95 over the
bodies of the standing value, the dynamic ease (largest increase over
standing through the motion) and the largest decrease; for each zone: of
the required stretch (the largest 95th-percentile skin stretch through the
motion), the largest mean stretch and the largest area change. Group "all"
pools every body. Lengths in cm and strains in % here, at the user's edge.
"""

from __future__ import annotations

import csv
import io
import json
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.dataset as ds

from hitogata.errors import HitogataError
from hitogata.export.atomic import write_bytes_atomically
from hitogata.study.runner import FAILED, ROWS

PERCENTILES = (5, 50, 95)
# (row kinds, column, quantity name, unit, scale from the column's unit)
QUANTITIES = (
    (("girth", "length", "height"), "standing_m", "standing", "cm", 100.0),
    (("girth", "length", "height"), "ease_increase_m", "dynamic_ease", "cm", 100.0),
    (("girth", "length", "height"), "ease_decrease_m", "largest_decrease", "cm", 100.0),
    (("zone",), "stretch_p95_pct", "required_stretch", "%", 1.0),
    (("zone",), "stretch_mean_pct", "mean_stretch", "%", 1.0),
    (("zone",), "area_change_pct", "area_change", "%", 1.0),
)


def read_rows(out: str | os.PathLike) -> dict[str, np.ndarray]:
    """Every row of a study's results folder, as columns (the motion from the partitioning)."""
    folder = Path(out) / ROWS
    if not folder.is_dir():
        raise HitogataError(f"{out}: no {ROWS}/ folder; allowed the --out folder of `hitogata study`")
    table = ds.dataset(str(folder), format="parquet", partitioning="hive").to_table()
    table = table.set_column(table.schema.get_field_index("motion"), "motion",
                             table.column("motion").cast(pa.string()))
    return {name: np.asarray(table.column(name).to_pylist(), dtype=object if table.schema.field(name).type
                             == pa.string() else float) for name in table.column_names}


def read_failures(out: str | os.PathLike) -> list[dict]:
    """The failed tasks' records (task, body, group, motion, error), by body and motion."""
    folder = Path(out) / FAILED
    entries = [json.loads(p.read_text(encoding="utf-8")) for p in folder.glob("*.json")] if folder.is_dir() else []
    return sorted(entries, key=lambda e: (e["body"], e["motion"]))


@dataclass(frozen=True)
class Band:
    """One line of a percentile table."""

    group: str
    motion: str
    kind: str
    name: str
    quantity: str
    unit: str
    n: int
    p5: float
    p50: float
    p95: float


def percentile_table(rows: dict[str, np.ndarray]) -> list[Band]:
    """P5/P50/P95 per group (and "all"), motion, measurement or zone, and quantity."""
    bands = []
    groups = ["all"] + sorted(set(rows["group"].tolist()))
    for motion in sorted(set(rows["motion"].tolist())):
        for group in groups:
            chosen = rows["motion"] == motion
            if group != "all":
                chosen &= rows["group"] == group
            for kinds, column, quantity, unit, scale in QUANTITIES:
                for kind in kinds:
                    names = [n for n in dict.fromkeys(rows["name"][chosen & (rows["kind"] == kind)].tolist())]
                    for name in names:
                        values = rows[column][chosen & (rows["kind"] == kind) & (rows["name"] == name)] * scale
                        values = values[np.isfinite(values)]
                        if not len(values):
                            continue
                        p = np.percentile(values, PERCENTILES)
                        bands.append(Band(group, motion, kind, name, quantity, unit, len(values), *map(float, p)))
    return bands


def bands_csv(bands: list[Band]) -> str:
    """The percentile table as CSV, units in the columns' values (`unit`) and header."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(["group", "motion", "kind", "name", "quantity", "unit", "n", "p5", "p50", "p95"])
    for b in bands:
        writer.writerow([b.group, b.motion, b.kind, b.name, b.quantity, b.unit, b.n,
                         f"{b.p5:.4g}", f"{b.p50:.4g}", f"{b.p95:.4g}"])
    return buffer.getvalue()


def failures_csv(failures: list[dict]) -> str:
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(["body", "group", "motion", "task", "error"])
    for f in failures:
        writer.writerow([f["body"], f["group"], f["motion"], f["task"], f["error"]])
    return buffer.getvalue()


def write_tables(out: str | os.PathLike) -> tuple[list[Band], dict[str, Path]]:
    """Write `percentiles.csv` and `failed.csv` into the results folder, atomically."""
    out = Path(out)
    bands = percentile_table(read_rows(out))
    written = {"percentiles": write_bytes_atomically(out / "percentiles.csv", bands_csv(bands).encode()),
               "failed": write_bytes_atomically(out / "failed.csv", failures_csv(read_failures(out)).encode())}
    return bands, written
