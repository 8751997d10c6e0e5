"""Is a held posture's quasi-static answer an equilibrium or an iteration count? At each extreme pose
(`hitogata.skeleton.extreme_poses`), the quasi-statics as `elastic_pose` runs it (from rest, the step cap
`STATIC_ITERATIONS`, then the floor repairs): its last step (mm; converged at ≤ 0.01 mm), its CPU
seconds, and how far a relative nudge of the skinned nodes (1e-14, a few units of round-off) moves the corner
nodes and the skin's elastic offset (mm). A converged solve moves by about the nudge; one that runs to its cap
moves by whatever round-off decides (docs/decisions/0035-a-held-posture-decided-by-round-off.md).
`--acceleration` picks the steps' (chebyshev: `HELD`, as a held posture takes them, with `--radius`; plain;
anderson: as a motion's frames); `--steps` the cap; `--against-plain` also solves plain steps to 2,000 and
prints how far the skin lies from their equilibrium (docs/decisions/0062-a-held-posture-by-chebyshev-steps.md).

    PYTHONPATH=src nice -n 5 python benchmarks/quasistatic_sensitivity.py [female|male ...] [--nudge 1e-14]
        [--steps 500] [--acceleration chebyshev|plain|anderson] [--radius 0.97] [--against-plain]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from hitogata.body import default_body
from hitogata.dynamics.quasistatic import FRAME, HELD, Acceleration, Chebyshev
from hitogata.dynamics.quality import STATIC_ITERATIONS
from hitogata.skin.single_pose import elastic_dynamics
from hitogata.skeleton.extreme_poses import extreme_poses

PLAIN_CAP = 2000


def main(sexes: list[str], nudge: float, steps: int, acceleration: Acceleration, against_plain: bool) -> None:
    rng = np.random.default_rng(0)
    extra = " skin from plain steps' equilibrium mm |" if against_plain else ""
    print(f"| body | pose | last step mm | CPU s | nodes moved by a {nudge:g} nudge mm | skin offset moved mm |{extra}")
    print("|---|---|---:|---:|---:|---:|" + ("---:|" if against_plain else ""))
    total = 0.0
    for sex in sexes:
        dynamics = elastic_dynamics(default_body(sex))
        for name, clinical in extreme_poses(dynamics.poser.skeleton).items():
            posed = dynamics.poser.pose(clinical=clinical, skinning=dynamics.rig.method)
            g, r = dynamics.rig.pose(posed.pose.rotations, posed.pose.translations)
            cpu = time.process_time()
            delta, size = dynamics.quasi_static(g[0], r[0], None, None, steps, acceleration=acceleration)
            cpu = time.process_time() - cpu
            total += cpu
            nudged = g[0] * (1.0 + nudge * rng.standard_normal(g[0].shape))
            other, _ = dynamics.quasi_static(nudged, r[0], None, None, steps, acceleration=acceleration)
            nodes = float(np.abs(other - delta).max()) * 1e3
            skin = float(np.abs(dynamics.rig.skin_map @ (other - delta)).max()) * 1e3
            line = f"| {sex} | {name} | {size * 1e3:.4f} | {cpu:.2f} | {nodes:.2g} | {skin:.2g} |"
            if against_plain:
                plain, _ = dynamics.quasi_static(g[0], r[0], None, None, PLAIN_CAP, acceleration=None)
                line += f" {float(np.abs(dynamics.rig.skin_map @ (delta - plain)).max()) * 1e3:.3g} |"
            print(line, flush=True)
    print(f"CPU of the solves: {total:.1f} s")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("sexes", nargs="*", default=["female", "male"])
    parser.add_argument("--nudge", type=float, default=1e-14, help="relative nudge of the skinned nodes")
    parser.add_argument("--steps", type=int, default=STATIC_ITERATIONS, help="the steps' cap")
    parser.add_argument("--acceleration", choices=("chebyshev", "plain", "anderson"), default="chebyshev")
    parser.add_argument("--radius", type=float, default=HELD.spectral_radius,
                        help="Chebyshev's spectral radius (the held posture's default)")
    parser.add_argument("--against-plain", action="store_true",
                        help=f"also solve plain steps (cap {PLAIN_CAP}) and print the skin's distance from them")
    args = parser.parse_args()
    chosen = {"chebyshev": Chebyshev(args.radius, HELD.plain_steps), "plain": None, "anderson": FRAME}
    main(args.sexes, args.nudge, args.steps, chosen[args.acceleration], args.against_plain)
