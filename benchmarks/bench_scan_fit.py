"""Scan-fit benchmark: a body fitted to a 100k-point scan, end to end and by stage.

Goal (the made-to-measure issue): a scan fit of a 100k-point scan ≤ 30 s.
The scan is made from a body of known shape (`hitogata.made_to_measure.scan_fit.synthetic`: 1.5 mm
noise, holes under the arms and between the legs, a rigid offset, millimetres),
so the figures printed beside the time are the fit's own errors: scan → body
distance and the largest measurement difference from the known body.
Stages, timed apart: the rigid start (24 axis matchings × 2 arm poses), the
shape-and-pose registration (two starts tried, then the rest of the iterations),
and the rest of `fit_scan` (detail, distances, measurements, scan girths).
"""

from __future__ import annotations

import time

import numpy as np

from hitogata.body import Body
from hitogata.made_to_measure.scan_fit import fit_scan, make_scan
from hitogata.made_to_measure.scan_fit.align import initial_alignments
from hitogata.made_to_measure.scan_fit.model import BodyModel
from hitogata.made_to_measure.scan_fit.register import register
from hitogata.made_to_measure.scan_fit.scanfit import FIT_POINTS, ITERATIONS
from hitogata.made_to_measure.scan_fit.synthetic import Perturbation, synthetic_scan
from hitogata.measure import measure
from hitogata.posing.pose import shipped_lists
from hitogata.body.shape import ShapeParameters

POINTS = 100_000
TRUTH = ShapeParameters(sex=0.0, age=40.0, weight=0.7, muscle=0.4, height=0.6, proportions=0.6, cup=0.7)


def main() -> None:
    body = Body.from_parameters(TRUTH)
    cloud, _ = synthetic_scan(body, body.vertices, body.rig.heads, Perturbation(), points=POINTS)
    scan = make_scan(cloud, None, "benchmark scan")
    measure(body)  # landmarks and tape skin of the known body, outside the timing
    shipped_lists()  # the skeleton and muscle lists read once, as for any later fit in a process

    start = time.perf_counter()
    fit = fit_scan(scan, "female")
    total = time.perf_counter() - start

    model = BodyModel(ShapeParameters(sex=0.0), body.density)
    t0 = time.perf_counter()
    starts = initial_alignments(model, scan.points)
    t1 = time.perf_counter()
    register(model, scan.sample(FIT_POINTS), starts[0], ITERATIONS)
    t2 = time.perf_counter()

    known, fitted = measure(body).as_dict(), fit.measurements.as_dict()
    worst = max(known, key=lambda n: abs(fitted[n] - known[n]))
    print(f"scan fit of a {len(scan.points):,}-point scan: {total:.1f} s (goal ≤ 30 s)")
    print(f"  rigid start {t1 - t0:.1f} s; registration, {ITERATIONS} iterations on {FIT_POINTS} points: "
          f"{t2 - t1:.1f} s (one start; the fit tries two for its first iterations)")
    e0, e1 = fit.model_error, fit.error
    print(f"  scan → body distance, shape model: median {e0.median * 1000:.2f} mm, 95th % {e0.p95 * 1000:.2f} mm, "
          f"max {e0.max * 1000:.2f} mm")
    print(f"  scan → body distance, with detail: median {e1.median * 1000:.2f} mm, 95th % {e1.p95 * 1000:.2f} mm, "
          f"max {e1.max * 1000:.2f} mm")
    print(f"  largest measurement difference from the known body: {worst} "
          f"{(fitted[worst] - known[worst]) * 1000:+.1f} mm")
    detail = np.abs(fit.offsets) if fit.offsets is not None else np.zeros(1)
    print(f"  detail: mean |offset| {detail.mean() * 1000:.2f} mm, max {detail.max() * 1000:.2f} mm")


if __name__ == "__main__":
    main()
