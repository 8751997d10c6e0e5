"""The skin's contact solve at the peaks of the mobility motions, with and without the trust region after a
costly cut step (`geometry.barrier_contact.BarrierSettings.sweep_pairs`), in the same run.

For each body and motion, the motion's peak posture (`motion.clip.peak_clip`) held elastic with contact
(`elastic_pose(..., contact=True)`, as `hitogata ease --surface elastic` holds a frame): wall and CPU
seconds (the process's, so the contact's threads count), the Newton iterations per path step, and the
largest distance (mm) between the two skins. "before" offers every Newton step in full (the trust region
off: `sweep_pairs` set past any sweep, through `elastic_pose(..., settings=)`); the ratio is before / now. The model is built (or read from the
disk cache) first and not timed. Prints a Markdown table (docs/decisions).

    PYTHONPATH=src python benchmarks/bench_contact_trust.py [female|male ...] [--motions arms_crossed,sit]
        [--now-only]
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace

import numpy as np

from hitogata.body import default_body
from hitogata.commands.ease import DEFAULT_MOTIONS
from hitogata.skin.single_pose import elastic_dynamics, elastic_pose
from hitogata.motion.clip import peak_clip, scenario_clip
from hitogata.motion.scenario import load_scenario, shipped_scenarios
from hitogata.posing import poser_for
from hitogata.skin.settings import SKIN_DEFAULTS

# the trust region off: no sweep is costly, every Newton step offered in full
NO_TRUST = replace(SKIN_DEFAULTS, barrier=replace(SKIN_DEFAULTS.barrier, sweep_pairs=int(np.iinfo(np.int64).max)))


def held(dynamics, angles: np.ndarray, trust: bool):
    """The held posture with contact, its wall and CPU seconds, with the trust region on or off."""
    wall, cpu = time.perf_counter(), time.process_time()
    pose = elastic_pose(dynamics, angles=angles, contact=True, on_limit="clamp",
                        settings=SKIN_DEFAULTS if trust else NO_TRUST)
    return pose, time.perf_counter() - wall, time.process_time() - cpu


def main(sexes: list[str], motions: list[str], baseline: bool) -> None:
    print("| body | motion | before wall s | before CPU s | now wall s | now CPU s | CPU ratio | Newton its now "
          "| skins differ mm |")
    print("|---|---|---:|---:|---:|---:|---:|---|---:|")
    shipped = shipped_scenarios()
    for sex in sexes:
        body = default_body(sex)
        dynamics = elastic_dynamics(body)
        poser = poser_for(body)
        totals = np.zeros(4)
        for motion in motions:
            angles = peak_clip(scenario_clip(load_scenario(shipped[f"mobility_{motion}"]), poser)).angles[1]
            now, wall, cpu = held(dynamics, angles, trust=True)
            iterations = now.barrier.iterations if now.barrier is not None else []
            if baseline:
                before, wall0, cpu0 = held(dynamics, angles, trust=False)
                differ = float(np.linalg.norm(now.vertices - before.vertices, axis=1).max()) * 1e3
                totals += (wall0, cpu0, wall, cpu)
                print(f"| {sex} | {motion} | {wall0:.1f} | {cpu0:.1f} | {wall:.1f} | {cpu:.1f} | {cpu0 / cpu:.1f} "
                      f"| {iterations} | {differ:.2f} |", flush=True)
            else:
                totals += (0.0, 0.0, wall, cpu)
                print(f"| {sex} | {motion} | – | – | {wall:.1f} | {cpu:.1f} | – | {iterations} | – |", flush=True)
        ratio = f"{totals[1] / totals[3]:.1f}" if baseline else "–"
        print(f"| {sex} | all | {totals[0]:.1f} | {totals[1]:.1f} | {totals[2]:.1f} | {totals[3]:.1f} | {ratio} | | |",
              flush=True)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("sexes", nargs="*", default=["female", "male"])
    parser.add_argument("--motions", default=DEFAULT_MOTIONS, help="comma-separated mobility motions")
    parser.add_argument("--now-only", action="store_true", help="skip the run without the trust region")
    args = parser.parse_args()
    main(args.sexes, args.motions.split(","), not args.now_only)
