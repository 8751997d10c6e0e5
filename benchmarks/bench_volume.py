"""Volume-model benchmark: the default female trunk at three sizes, then the whole body over the body grid.

Part 1, per trunk size: tets, nodes, the time of the mesher alone (`stuff`)
and of the whole labelled model, minimum/maximum dihedral angle, inverted
tets, volume error against the skin, mean and max (Hausdorff) surface
distance, region volumes.

Part 2, the whole body at the elastic default (40 mm, soft tissue round the
bone capsules) over the grid of `tests/volume/test_body_mesh_grid.py`: the stuffed
mesh as it was (the baseline, measured in the same run: `stuff` alone) and
after `hitogata.volume.repair`, each with `hitogata.volume.integrity`'s
figures (pieces, pinched vertices and edges, non-manifold boundary edges
and vertices, weakest hold, min dihedral); the repaired model's build time,
volume error, surface distance (mean; max; the 95th percentile of the skin
vertices' distance to the mesh) and, with `--modes`, its lowest frequency
(P2, rigid bone, the elastic default).

Run:  python benchmarks/bench_volume.py [--grid-only] [--modes]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from hitogata.body import Body, default_body
from hitogata.elastic.model import EIGEN_TOLERANCE, assemble_system
from hitogata.fem import solve_modes
from hitogata.volume import anatomy as A
from hitogata.volume.bones import PART, outside_capsules
from hitogata.volume.domain import Intersection
from hitogata.volume.integrity import mesh_integrity
from hitogata.volume.lattice import stuff
from hitogata.volume.model import build_trunk_model, build_volume_model
from hitogata.volume.surface import SurfaceIndex
from hitogata.volume.trunk import body_domain, trunk_domain

SIZES_MM = (30.0, 20.0, 10.0)
BODY_SIZE_MM = 40.0  # the elastic body's default (P2)
# (label, sex, stature m, mass kg): the CLI's default body, the demo's two defaults, then the
# corners of the supported range (stature 150-195 cm, BMI 18-35; women to 33: docs/body.md).
GRID = [("cli female 165 cm 60 kg", "female", 1.65, 60.0), ("default female", "female", None, None),
        ("default male", "male", None, None)] + [
    (f"{sex} {s * 100:.0f} cm BMI {bmi:.0f}", sex, s, round(bmi * s * s, 1))
    for sex, bmis in (("female", (18.0, 33.0)), ("male", (18.0, 35.0))) for s in (1.50, 1.95) for bmi in bmis
] + [("female 165 cm BMI 26", "female", 1.65, round(26.0 * 1.65 ** 2, 1)),
     ("male 178 cm BMI 30", "male", 1.78, round(30.0 * 1.78 ** 2, 1))]


def grid_body(sex: str, stature: float | None, mass: float | None) -> Body:
    return default_body(sex) if stature is None else Body.from_measurements(sex, 30.0, stature, mass)


def trunk_sizes() -> None:
    body = default_body("female")
    print(f"default female: stature {body.stature:.3f} m, BMI {body.bmi:.1f}")
    for size in SIZES_MM:
        domain, bounds = trunk_domain(body.vertices, body.faces, body.rig, body.skin_weights)
        t = time.perf_counter()
        stuff(domain, size * 1e-3, bounds)
        mesher = time.perf_counter() - t
        t = time.perf_counter()
        model = build_trunk_model(body, element_size=size)
        total = time.perf_counter() - t
        print(f"trunk h = {size:.0f} mm: mesher {mesher:.2f} s, labelled model {total:.2f} s")
        print("  " + model.quality.summary())


def stuffed_integrity(body: Body):
    """The whole body's mesh as stuffed, before the repair (the baseline), and its integrity."""
    rows = [body.rig.names.index(n) for n in A.BODY_BONES]
    heads, tails = body.rig.heads[rows], body.rig.tails[rows]
    skin, bounds = body_domain(body.vertices, body.faces)
    domain = Intersection(skin, outside_capsules(heads, tails, A.capsule_radii(A.BODY_BONES)))
    mesh = stuff(domain, BODY_SIZE_MM * 1e-3, bounds)
    return mesh_integrity(mesh.nodes, mesh.tets, np.flatnonzero(mesh.node_part == domain.parts.index(PART)))


def body_grid(modes: bool) -> None:
    print(f"\nwhole body at {BODY_SIZE_MM:.0f} mm (load average {os.getloadavg()[0]:.2f})")
    print("pieces / pinched vertices / pinched edges / non-manifold boundary edges / vertices / weakest hold (mm) / "
          "min dihedral; before = as stuffed, after = repaired")
    for label, sex, stature, mass in GRID:
        body = grid_body(sex, stature, mass)
        before = stuffed_integrity(body)
        t = time.perf_counter()
        volume = build_volume_model(body.vertices, body.faces, body.rig, body.skin_weights, bmi=body.bmi,
                                    sex=body.params.sex, extent="body", element_size=BODY_SIZE_MM)
        build = time.perf_counter() - t
        q, after, fix = volume.quality, volume.quality.integrity, volume.quality.repaired
        skin = SurfaceIndex(volume.nodes, volume.boundary_faces).distance(body.vertices)
        line = (f"{label:26s} BMI {body.bmi:4.1f}  before {_figures(before)}  after {_figures(after)}  "
                f"split {fix.split}, removed {fix.pinched + fix.unheld} tets {fix.removed_volume * 1e3:.2f} L; "
                f"build {build:.1f} s; volume {q.volume_error * 100:+.2f}%; surface mean {q.surface_distance_mean * 1e3:.2f} "
                f"mm, max {q.surface_distance_max * 1e3:.0f} mm, skin p95 {np.percentile(skin, 95) * 1e3:.0f} mm")
        if modes:
            t = time.perf_counter()
            system = assemble_system(volume, body.rig)
            f = solve_modes(system.K, system.M, 3, system.fixed_nodes, tol=EIGEN_TOLERANCE).frequencies
            line += f"; f1-3 {f[0]:.3f} {f[1]:.3f} {f[2]:.3f} Hz ({time.perf_counter() - t:.1f} s)"
        print(line, flush=True)


def _figures(m) -> str:
    return (f"{m.n_pieces}/{m.pinched_vertices}/{m.pinched_edges}/{m.non_manifold_edges}/{m.non_manifold_vertices}/"
            f"{m.weakest_hold * 1e3:.0f}/{m.min_dihedral:.1f}°")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid-only", action="store_true", help="skip the trunk sizes")
    parser.add_argument("--modes", action="store_true", help="also the lowest frequencies of the whole body")
    args = parser.parse_args()
    if not args.grid_only:
        trunk_sizes()
    body_grid(args.modes)


if __name__ == "__main__":
    main()
