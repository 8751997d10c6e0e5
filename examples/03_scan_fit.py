"""A body fitted to a scan. The scan is made here from a body of known shape (the library's own
synthetic scan: a point cloud with 1.5 mm noise, holes under the arms and at the crotch, turned,
moved and written in millimetres), so the fit can be checked against the truth.

    python examples/03_scan_fit.py [OUT_FOLDER]

With a real scan: `hitogata fit scan.ply --sex female --out fitted.glb` (docs/body.md).
"""

import sys
import tempfile
from pathlib import Path

import hitogata as hg
from hitogata.made_to_measure.scan_fit import fit_scan, make_scan  # scan fitting: the functions behind `hitogata fit`
from hitogata.made_to_measure.scan_fit.synthetic import synthetic_scan

out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="hitogata-03-"))
out.mkdir(parents=True, exist_ok=True)

truth = hg.Body.from_measurements(sex="male", age=40, stature=1.78, mass=80.0)
cloud, faces = synthetic_scan(truth, truth.vertices, truth.rig.heads, points=30_000)  # millimetres
scan = make_scan(cloud, faces, "synthetic scan")  # the unit (mm) is found from the extent
print(f"scan: {len(scan.points)} points in {scan.unit}")

fit = fit_scan(scan, "male", detail=False)  # detail=True adds per-vertex offsets along the normals
print(f"scan to body: median {fit.error.median * 1000:.1f} mm, 95th percentile {fit.error.p95 * 1000:.1f} mm")
for name in ("chest_girth", "waist_girth", "hip_girth"):
    made, known = fit.measurements.get(name), hg.measure(truth).get(name)
    print(f"{name:12s} fitted {made * 100:6.1f} cm, known {known * 100:6.1f} cm, {(made - known) * 1000:+5.1f} mm")
print("regions the shape model cannot follow:", ", ".join(fit.not_followed) or "none")

path = hg.write_body(out / "fitted.glb", fit.body)
print(f"wrote {path}")
