"""What `hitogata fit` prints and writes beside the body: fit errors, regions, measurements side by side."""

from __future__ import annotations

import json
import math
import os
from dataclasses import asdict
from pathlib import Path

import numpy as np

from hitogata.export.atomic import write_bytes_atomically
from hitogata.export.body_files import shape_extras
from hitogata.made_to_measure.scan_fit.scanfit import Distances, ScanFit
from hitogata.report.measurements import LABELS


def _mm(d: Distances) -> dict[str, float]:
    return {f"{k}_mm": round(v * 1000, 2) for k, v in asdict(d).items()}


def _cm(value: float) -> float | None:
    return None if not math.isfinite(value) else round(value * 100, 2)


def fit_summary(fit: ScanFit, scan: str, unit: str) -> dict[str, object]:
    """The fit as JSON-able data: lengths in mm (errors) and cm (measurements), angles in degrees."""
    rest, posed = fit.measurements.as_dict(), fit.posed_measurements.as_dict()
    offsets = np.zeros(1) if fit.offsets is None else np.abs(fit.offsets)
    return {
        "scan": scan,
        "scan_unit": unit,
        "shape": shape_extras(fit.body.params),
        "scan_pose_deg": {k: round(math.degrees(v), 2) for k, v in fit.pose.items()},
        "error_shape_model": _mm(fit.model_error),
        "error_fitted_body": _mm(fit.error),
        "detail": {"applied": fit.offsets is not None, "mean_abs_mm": round(float(offsets.mean()) * 1000, 2),
                   "max_abs_mm": round(float(offsets.max()) * 1000, 2)},
        "regions_shape_model": [
            {"region": r.region, "points": r.points, "median_mm": round(r.median * 1000, 2),
             "p95_mm": round(r.p95 * 1000, 2), "outside_mm": round(r.outside * 1000, 2)} for r in fit.regions
        ],
        "cannot_follow": fit.not_followed,
        "measurements_cm": {
            name: {"scan": _cm(fit.scan_girths.get(name, float("nan"))), "fitted_scan_pose": _cm(posed[name]),
                   "fitted_rest": _cm(rest[name])}
            for name in rest
        },
    }


def fit_text(summary: dict) -> str:
    """The printed report of `fit_summary`'s data."""
    e0, e1 = summary["error_shape_model"], summary["error_fitted_body"]
    lines = [
        "scan → body distance (mm)   median   95th %     max",
        f"  shape model              {e0['median_mm']:7.2f}  {e0['p95_mm']:7.2f}  {e0['max_mm']:7.2f}",
        f"  fitted body (+ detail)   {e1['median_mm']:7.2f}  {e1['p95_mm']:7.2f}  {e1['max_mm']:7.2f}",
        "",
        "shape model per region (mm): median  95th %  outside",
    ]
    for r in summary["regions_shape_model"]:
        flag = "  ← cannot follow" if r["region"] in summary["cannot_follow"] else ""
        lines.append(f"  {r['region']:<16} {r['median_mm']:7.2f} {r['p95_mm']:7.2f} {r['outside_mm']:+8.2f}{flag}")
    if summary["cannot_follow"]:
        lines.append(f"the shape model cannot follow the scan at: {', '.join(summary['cannot_follow'])} "
                     "(the detail takes up to its cap there)")
    width = max(len(label) for label in LABELS.values())
    head = f"{'measurement (cm)':<{width}}  {'scan':>7}  {'fitted':>7}  {'at rest':>7}"
    lines += ["", head, "-" * len(head)]
    for name, row in summary["measurements_cm"].items():
        scan = "—" if row["scan"] is None else f"{row['scan']:.1f}"
        fitted = "—" if row["fitted_scan_pose"] is None else f"{row['fitted_scan_pose']:.1f}"
        rest = "—" if row["fitted_rest"] is None else f"{row['fitted_rest']:.1f}"
        lines.append(f"{LABELS[name]:<{width}}  {scan:>7}  {fitted:>7}  {rest:>7}")
    lines.append("(scan: girths taken on the scan in the fitted body's planes; fitted: the fitted body in the scan's "
                 "pose; at rest: the body as written)")
    return "\n".join(lines)


def write_summary(path: str | os.PathLike, summary: dict) -> Path:
    """The summary as JSON, atomically."""
    return write_bytes_atomically(path, summary_bytes(summary))


def summary_bytes(summary: dict) -> bytes:
    """The summary's JSON file."""
    return (json.dumps(summary, indent=1, allow_nan=False) + "\n").encode()
