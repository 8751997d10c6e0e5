"""Write the shipped example mesh garment, `src/hitogata/data/garments/legging_mesh.obj`, from the legging.

The mesh is the shipped legging (−20 % ease) sewn for the default female body, in its rest (relaxed)
shape as the tubular garment's dressing builds it: at each of the garment's stations a ring of
`PER_RING` vertices, a regular polygon of that station's relaxed circumference, the rings stacked
straight at the stations' spacing (metres, OBJ). Dressed by `legging_mesh.toml` on the default female
it is the same garment as `legging`: a test compares their pressures.

    python tools/generate_garment_mesh.py                 # rewrites the shipped file
    python tools/generate_garment_mesh.py --out /tmp/legging_mesh.obj
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from hitogata.body import default_body
from hitogata.garment.contact.dressing import prepare
from hitogata.garment.contact.spec import load_garment
from hitogata.garment.contact.tube import polygon_radius, ring_faces

PER_RING = 32  # vertices round a ring (a polygon's perimeter is its relaxed circumference at any count)
SHIPPED = Path(__file__).resolve().parents[1] / "src" / "hitogata" / "data" / "garments" / "legging_mesh.obj"


def legging_rings() -> tuple[np.ndarray, np.ndarray]:
    """The legging's rest rings on the default female: vertices (M·N, 3) m and faces."""
    _, tube, _, _, _, _ = prepare(default_body("female"), load_garment("legging"))
    origins = tube.stations.origins
    heights = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(origins, axis=0), axis=1))])
    # a ring at every station: the garment's pressure follows its strain, 4 × as sensitive as its relaxed
    # size (at 25 % strain), and a ring at every second station misses the ankle's curve by 1.3 %
    radius = polygon_radius(tube.relaxed, PER_RING)
    angle = 2 * np.pi * np.arange(PER_RING) / PER_RING
    vertices = np.stack([radius[:, None] * np.cos(angle), radius[:, None] * np.sin(angle),
                         np.broadcast_to(heights[:, None], (len(heights), PER_RING))], axis=-1).reshape(-1, 3)
    return vertices, ring_faces(len(heights), PER_RING)


def obj_text(vertices: np.ndarray, faces: np.ndarray) -> str:
    """An OBJ of the mesh (metres), one-based faces."""
    lines = ["# hitogata example garment: the legging (-20 % ease) sewn for the default female, rest shape, metres"]
    lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=SHIPPED)
    args = parser.parse_args()
    args.out.write_text(obj_text(*legging_rings()), encoding="utf-8")
    print(args.out)


if __name__ == "__main__":
    main()
