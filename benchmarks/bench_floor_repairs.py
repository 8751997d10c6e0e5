"""The quasi-statics' floor repairs against those of a baseline commit, measured in the same run.

A floor repair holds each element that fell below the volume floor by a multiplier of its own
(`dynamics.quasistatic`). Each multiplier needs the Laplacian's response to the element's volume
gradient, L⁻¹g; this run's solver combines it from kept columns of L⁻¹ at the element's four corners
(`fem.factor.InverseColumns`), the baseline's back-substitutes every gradient at every repair step.

Measured on both default bodies, each with the elastic model `elastic_pose` uses:

- the 20 extreme poses' quasi-statics from rest (at most `STATIC_ITERATIONS` Anderson-accelerated steps,
  then the floor repairs): CPU seconds of each solver and the largest distance between their skins (mm);
- a motion (`mobility_deep_squat` at 5 frames/s, `simulate`): CPU seconds and the largest distance
  between the skins of any frame (mm).

The skins agree where the solve converges; where the floor repairs' held set is decided by round-off
(the seated 90/90 pose, the motion's deepest frames) they differ by what round-off decides
(docs/decisions/0035-a-held-posture-decided-by-round-off.md).

    PYTHONPATH=src python benchmarks/bench_floor_repairs.py [--base 7d2b7ae] [--sexes female male]
"""

from __future__ import annotations

import argparse
import copy
import dataclasses
import subprocess
import sys
import time
import types
from pathlib import Path

import numpy as np

from hitogata.body import default_body
from hitogata.dynamics.motion import simulate
from hitogata.dynamics.quality import STATIC_ITERATIONS
from hitogata.motion.scenario import load_scenario, shipped_scenarios
from hitogata.simulation.run import build_dynamics
from hitogata.skeleton.extreme_poses import extreme_poses
from hitogata.skin.single_pose import elastic_dynamics

ROOT = Path(__file__).resolve().parents[1]
MOTION = "mobility_deep_squat"


def baseline_class(base: str) -> type:
    """The QuasiStatic class of commit `base` (its own module, the rest of the package today's)."""
    source = subprocess.run(["git", "show", f"{base}:src/hitogata/dynamics/quasistatic.py"], cwd=ROOT,
                            capture_output=True, text=True, check=True).stdout
    module = types.ModuleType("baseline_quasistatic")
    exec(compile(source, f"{base}:quasistatic.py", "exec"), module.__dict__)
    sys.modules[module.__name__] = module
    return module.QuasiStatic


def with_solver(dynamics, solver: type):
    """A shallow copy of `dynamics` whose quasi-statics run `solver`'s methods on the same matrices."""
    statics = copy.copy(dynamics.statics)
    statics.__class__ = solver
    return dataclasses.replace(dynamics, statics=statics)


def held_poses(sex: str, old: type) -> None:
    dynamics = elastic_dynamics(default_body(sex))
    baseline = with_solver(dynamics, old)
    totals = {"today": 0.0, "baseline": 0.0}
    for name, clinical in extreme_poses(dynamics.poser.skeleton).items():
        posed = dynamics.poser.pose(clinical=clinical, skinning=dynamics.rig.method)
        g, r = dynamics.rig.pose(posed.pose.rotations, posed.pose.translations)
        skins, cpu = {}, {}
        for label, solver in (("today", dynamics), ("baseline", baseline)):
            start = time.process_time()
            delta, _ = solver.quasi_static(g[0], r[0], None, None, STATIC_ITERATIONS)
            cpu[label] = time.process_time() - start
            totals[label] += cpu[label]
            skins[label] = dynamics.rig.skin_map @ delta
        apart = float(np.linalg.norm(skins["today"] - skins["baseline"], axis=1).max()) * 1e3
        print(f"| {sex} | {name} | {cpu['baseline']:.2f} | {cpu['today']:.2f} | "
              f"{cpu['baseline'] / cpu['today']:.2f} | {apart:.3g} |", flush=True)
    print(f"| {sex} | all 10 | {totals['baseline']:.1f} | {totals['today']:.1f} | "
          f"{totals['baseline'] / totals['today']:.2f} | |", flush=True)


def motion(old: type) -> None:
    body = default_body("female")
    scenario = load_scenario(shipped_scenarios()[MOTION])
    dynamics = build_dynamics(body, scenario)
    skins, cpu = {}, {}
    for label, solver in (("today", dynamics), ("baseline", with_solver(dynamics, old))):
        start = time.process_time()
        result = simulate(solver, scenario.timeline, scenario.duration, 5.0, 1, scenario.model.gravity,
                          scenario.on_limit)
        cpu[label] = time.process_time() - start
        skins[label] = result.skin
    apart = np.linalg.norm(skins["today"] - skins["baseline"], axis=2).max(axis=1) * 1e3
    print(f"| female | {MOTION}, {len(apart)} frames at 5/s | {cpu['baseline']:.1f} | {cpu['today']:.1f} | "
          f"{cpu['baseline'] / cpu['today']:.2f} | {apart.max():.3g} (median frame {np.median(apart):.2g}) |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", default="7d2b7ae", help="the commit whose floor repairs are the baseline")
    parser.add_argument("--sexes", nargs="+", default=["female", "male"])
    args = parser.parse_args()
    old = baseline_class(args.base)
    print("| body | pose | baseline CPU s | today CPU s | ratio | skins apart mm |")
    print("|---|---|---:|---:|---:|---:|")
    for sex in args.sexes:
        held_poses(sex, old)
    motion(old)


if __name__ == "__main__":
    main()
