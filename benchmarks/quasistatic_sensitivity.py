"""Is a held posture's quasi-static answer an equilibrium or an iteration count? At each extreme pose
(`hitogata.skeleton.extreme_poses`), the quasi-statics as `elastic_pose` runs it (from rest, the step cap
`STATIC_ITERATIONS`, then the floor repairs): its last step (mm; converged at ≤ 0.01 mm), its CPU
seconds, and how far a relative nudge of the skinned nodes (1e-14, a few units of round-off) moves the corner
nodes and the skin's elastic offset (mm). A converged solve moves by about the nudge; one that runs to its cap
moves by whatever round-off decides (docs/decisions/0035-a-held-posture-decided-by-round-off.md).
`--steps` sets the steps' cap and `--memory` the floor repairs' Anderson memory (0, `STATIC_MEMORY`: plain
repair steps, as a held posture takes them; 5: as a motion's frames do), to tell the iteration's share of that
sensitivity from the floor repairs' (docs/decisions/0061-a-held-posture-that-converges.md).

    PYTHONPATH=src nice -n 5 python benchmarks/quasistatic_sensitivity.py [female|male ...] [--nudge 1e-14]
        [--steps 200] [--memory 0]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from hitogata.body import default_body
from hitogata.dynamics.quasistatic import MEMORY
from hitogata.dynamics.quality import STATIC_ITERATIONS, STATIC_MEMORY
from hitogata.skin.single_pose import elastic_dynamics
from hitogata.skeleton.extreme_poses import extreme_poses


def main(sexes: list[str], nudge: float, steps: int, memory: int) -> None:
    rng = np.random.default_rng(0)
    print(f"| body | pose | last step mm | CPU s | nodes moved by a {nudge:g} nudge mm | skin offset moved mm |")
    print("|---|---|---:|---:|---:|---:|")
    for sex in sexes:
        dynamics = elastic_dynamics(default_body(sex))
        for name, clinical in extreme_poses(dynamics.poser.skeleton).items():
            posed = dynamics.poser.pose(clinical=clinical, skinning=dynamics.rig.method)
            g, r = dynamics.rig.pose(posed.pose.rotations, posed.pose.translations)
            cpu = time.process_time()
            delta, size = dynamics.quasi_static(g[0], r[0], None, None, steps, memory=memory)
            cpu = time.process_time() - cpu
            nudged = g[0] * (1.0 + nudge * rng.standard_normal(g[0].shape))
            other, _ = dynamics.quasi_static(nudged, r[0], None, None, steps, memory=memory)
            nodes = float(np.abs(other - delta).max()) * 1e3
            skin = float(np.abs(dynamics.rig.skin_map @ (other - delta)).max()) * 1e3
            print(f"| {sex} | {name} | {size * 1e3:.4f} | {cpu:.2f} | {nodes:.2g} | {skin:.2g} |", flush=True)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("sexes", nargs="*", default=["female", "male"])
    parser.add_argument("--nudge", type=float, default=1e-14, help="relative nudge of the skinned nodes")
    parser.add_argument("--steps", type=int, default=STATIC_ITERATIONS, help="the plain steps' cap")
    parser.add_argument("--memory", type=int, default=STATIC_MEMORY,
                        help=f"the floor repairs' Anderson memory (0: plain steps; a motion's frames take {MEMORY})")
    args = parser.parse_args()
    main(args.sexes, args.nudge, args.steps, args.memory)
