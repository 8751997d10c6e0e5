"""A body from sex, age, stature and mass: its figures, its ISO 8559-1 measurements, a GLB file.

    python examples/01_body.py [OUT_FOLDER]

The library works in SI units (metres, kilograms); this script prints centimetres.
"""

import sys
import tempfile
from pathlib import Path

import hitogata as hg

out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="hitogata-01-"))
out.mkdir(parents=True, exist_ok=True)

# The shape is solved so that the body has this stature and mass (its volume times a whole-body density).
body = hg.Body.from_measurements(sex="female", age=30, stature=1.65, mass=58.0)
print(f"stature {body.stature * 100:.1f} cm, mass {body.mass:.1f} kg, BMI {body.bmi:.1f}, "
      f"volume {body.volume * 1000:.1f} L")
print(f"skin: {len(body.vertices)} vertices, {len(body.faces)} triangles; rig: {len(body.rig.names)} bones")

# Girths and lengths measured on the skin as a tape and a calliper would (docs/measurements.md).
m = hg.measure(body)
for name in ("chest_girth", "waist_girth", "hip_girth", "inside_leg"):
    print(f"{name:12s} {m.get(name) * 100:6.1f} cm")

# A GLB carries the rig and the skin weights, so Blender or three.js can pose it; .obj/.ply write the surface.
path = hg.write_body(out / "body.glb", body)
print(f"wrote {path}")
