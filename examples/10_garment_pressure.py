"""Garment pressure: a stretch garment (leggings, compression hosiery) on a body, standing and seated.

    python examples/10_garment_pressure.py [OUT_FOLDER]

At each level (ankle, calf, knee, thigh, hip, waist) the fabric's strain gives its tension, and
Laplace's law with the local curvature of the fabric's path gives the pressure round the girth
(docs/garment.md). The fabric here is linear, 400 N/m per unit strain; a tensile test's CSV
(`read_fabric_csv`) takes its place for a real fabric.
"""

import csv
import math
import sys
import tempfile
from pathlib import Path

import hitogata as hg
from hitogata.garment import Fabric, Garment, compression_class, garment_pressure

out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="hitogata-10-"))
out.mkdir(parents=True, exist_ok=True)

body = hg.default_body("female")
garment = Garment(ease=-0.15)  # 15 % smaller round than the standing body at every level
fabric = Fabric.linear(400.0)  # N/m per unit strain

standing = garment_pressure(body, garment, fabric)
seated = hg.pose_body(body, clinical={"thigh_r.flexion": math.radians(90), "shank_r.flexion": math.radians(90)},
                      skinning="dqs")
sitting = garment_pressure(body, garment, fabric, seated.vertices, seated.rig_joints)

print(f"{'level':6s} {'girth cm':>8s} {'standing mmHg mean/peak':>24s} {'seated strain %':>16s} {'mmHg mean/peak':>15s}")
rows = []
for level, at_rest in standing.items():
    a, b = at_rest.as_row(), sitting[level].as_row()
    print(f"{level:6s} {a['girth_cm']:8.1f} {a['mean_mmHg']:15.1f} / {a['peak_mmHg']:5.1f} "
          f"{b['strain_pct']:16.1f} {b['mean_mmHg']:8.1f} / {b['peak_mmHg']:5.1f}")
    rows += [{"posture": "standing", **a}, {"posture": "seated", **b}]
print("compression class at the ankle:", compression_class(standing["ankle"].mean_pressure))

with open(out / "pressure.csv", "w", newline="", encoding="utf-8") as f:
    writer = csv.DictWriter(f, fieldnames=list(rows[0]))
    writer.writeheader()
    writer.writerows(rows)
print(f"wrote {out / 'pressure.csv'}")
