"""Pose a body by its muscles and joint angles (the paper's eq. 1, 2), measure it and its skin strain.

    python examples/04_pose.py [OUT_FOLDER]

Contractions are fractions of a muscle's rest length (positive shortens, negative stretches);
clinical angles are radians from the anatomical position. `hitogata pose --list` prints every name.
"""

import math
import sys
import tempfile
from pathlib import Path

import hitogata as hg

out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="hitogata-04-"))
out.mkdir(parents=True, exist_ok=True)

body = hg.default_body("female")  # the shipped default woman: 30 years, 165 cm, 62 kg
rest = hg.pose_body(body)
posed = hg.pose_body(body, contractions={"biceps_brachii_l": 0.25},  # the biceps 25 % shorter bends the elbow
                     clinical={"shank_r.flexion": math.radians(60)})  # the right knee flexed to 60°

for dof in ("forearm_l.flexion", "shank_r.flexion"):
    before, after = (math.degrees(p.clinical[p.skeleton.dof_index(dof)]) for p in (rest, posed))
    print(f"{dof:18s} {before:6.1f}° -> {after:6.1f}°")

# Measurements follow the posture: the tape goes round the posed skin.
print(f"waist {hg.measure(body).waist_girth * 100:.1f} cm at rest, {hg.measure(posed).waist_girth * 100:.1f} cm posed")

# Skin strain per triangle from rest, summarised per garment zone (percent).
zones = hg.zone_strains(body, hg.skin_strain(body.vertices, posed.vertices, body.faces))
for name in sorted(zones, key=lambda z: -zones[z].stretch_p95)[:4]:
    z = zones[name]
    print(f"zone {name:16s} stretch p95 {z.stretch_p95:+5.1f} %, area {z.area_change:+5.1f} %")

# The GLB holds the rest skin bound to the 65 parts with the pose as joint rotations.
path = hg.write_posed(out / "posed.glb", hg.poser_for(body), posed)
print(f"wrote {path}")
