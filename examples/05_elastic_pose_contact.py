"""The elastic whole body held in a deep pose, with the skin's self-contact resolved.

    python examples/05_elastic_pose_contact.py [OUT_FOLDER]

With the elbow flexed to 150°, skinning alone pushes the forearm's skin into the upper arm's.
The elastic pose solves the finite-element body (co-rotational quasi-statics) for the pose;
`contact=True` then resolves the skin's self-contact with a barrier (IPC) reached through skinned
postures on the way, so no part of the skin passes into another, and ties the crease's skin back
towards the fascia (docs/elastic.md). The command line does the same with
`hitogata pose --angle elbow_l.flexion=150deg --elastic --contact --out elbow.glb`.
The elements here are coarser than the default 40 mm, to keep the run short.
"""

import math
import sys
import tempfile
from pathlib import Path

import hitogata as hg
from hitogata.skin import elastic_dynamics, elastic_pose  # the elastic pose behind `pose --elastic`

out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="hitogata-05-"))
out.mkdir(parents=True, exist_ok=True)

body = hg.default_body("female")
dynamics = elastic_dynamics(body, element_size=60.0)  # the whole body's elastic model (mm), built once per body
pose = {"forearm_l.flexion": math.radians(150)}

for contact in (False, True):
    held = elastic_pose(dynamics, clinical=pose, contact=contact)
    inside = held.penetrations  # skin vertices inside another part, beyond those of the rest body
    deepest = float(inside.depth.max()) * 1000 if len(inside) else 0.0
    label = "with contact   " if contact else "without contact"
    print(f"{label}: {len(inside):3d} skin vertices inside another part (deepest {deepest:4.1f} mm), "
          f"{held.quality.inverted} inverted elements")
    if contact:
        barrier = held.barrier
        print(f"barrier: {int(barrier.free.sum())} free skin vertices, Newton iterations per path step {barrier.iterations}, "
              f"smallest gap {barrier.min_distance * 1000:.2f} mm")

# The skin strain at the elbow's zone, contact resolved (percent; the fold of the crease shortens skin).
elbow = hg.zone_strains(body, hg.skin_strain(body.vertices, held.vertices, body.faces))["elbow_left"]
print(f"elbow zone: stretch p95 {elbow.stretch_p95:+.1f} %, compression mean {elbow.compression_mean:+.1f} %, "
      f"area {elbow.area_change:+.1f} %")
path = hg.write_mesh(out / "elbow_elastic.ply", held.vertices, held.faces)
print(f"wrote {path}")
