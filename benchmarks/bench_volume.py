"""Volume-model benchmark: meshing time and quality of the default female trunk at three element sizes.

Prints, per size: tets, nodes, the time of the mesher alone (`stuff`) and of the
whole labelled model, minimum/maximum dihedral angle, inverted tets, volume
error against the skin, mean and max (Hausdorff) surface distance, region volumes.
"""

from __future__ import annotations

import time

from hitogata.body import default_body
from hitogata.volume.model import build_trunk_model
from hitogata.volume.lattice import stuff
from hitogata.volume.trunk import trunk_domain

SIZES_MM = (30.0, 20.0, 10.0)


def main() -> None:
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


if __name__ == "__main__":
    main()
