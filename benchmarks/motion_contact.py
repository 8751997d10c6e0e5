"""Self-contact through a motion (`simulate(..., contact=True)`: `hitogata.skin.motion_contact`, the
IPC barrier frame to frame) against the motion without it, and what it costs.

A shipped scenario (default `elbow_flexion_body`: the left elbow to 150° and back) run on a default
body's whole-body model (`single_pose.elastic_dynamics`: 40 mm, 2 modes) at a given rate, with and
without contact, in one process. Per frame: new self-crossing triangle pairs beyond the rest body's
(`geometry.self_intersections`) and skin vertices inside another part (`SelfContact.penetrations`)
both ways; with contact the free skin, Newton iterations, the smallest gap left and the contact's
seconds; and a line drawn on the skin (`measure.body_lines`, default the front of the elbow), its % change
of length on the fine skin by skinning, without and with contact (the creases tied back frame by frame:
`skin.creases`). Then each run's skin checks (`run.surface_problems`) and the whole motion's time both ways.

    PYTHONPATH=src python benchmarks/motion_contact.py [female|male ...] [--rate 5] [--scenario NAME] [--line NAME]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from hitogata.body import default_body
from hitogata.simulation.run import surface_problems
from hitogata.motion.scenario import load_scenario, shipped_scenarios
from hitogata.skin.single_pose import elastic_dynamics
from hitogata.dynamics.motion import Motion
from hitogata.geometry import self_intersections, surface_integrity
from hitogata.measure.body_lines import body_lines
from hitogata.skeleton.kinematics import Pose
from hitogata.skin.contact import skin_contact
from hitogata.skin.fine_skin import body_fine_skinning
from hitogata.skin.motion_contact import simulate


def crossing_pairs(v: np.ndarray, faces: np.ndarray) -> set[tuple[int, int]]:
    return set(map(tuple, self_intersections(v, faces).tolist()))


def line_change(motion: Motion, skins: np.ndarray, line: str) -> list[float]:
    """% change of a line's length on the fine skin carried by `skins` (F, V, 3), per frame."""
    body = motion.dynamics.poser.body
    fine = body_fine_skinning(body)
    drawn = body_lines(body, fine.fine.vertices, fine.fine.faces)[line]
    rest = drawn.length(fine.fine.vertices)
    poses = [Pose(motion.dynamics.poser.skeleton, motion.rotations[k:k + 1], motion.translations[k:k + 1])
             for k in range(len(skins))]
    return [(drawn.length(fine.surface(p, motion.dynamics.rig.method, x.astype(float))) / rest - 1) * 100
            for p, x in zip(poses, skins)]


def main(sexes: list[str], rate: float, name: str, line: str) -> None:
    scenario = load_scenario(shipped_scenarios()[name])
    for sex in sexes:
        body = default_body(sex)
        dynamics = elastic_dynamics(body, n_modes=2)  # a motion's dynamics: its two lowest modes
        test = skin_contact(dynamics.poser)
        rest = crossing_pairs(body.vertices, body.faces)
        runs, seconds = {}, {}
        for contact in (False, True):
            start = time.perf_counter()
            runs[contact] = simulate(dynamics, scenario.timeline, scenario.duration, rate, 1, scenario.model.gravity,
                                     scenario.on_limit, contact=contact)
            seconds[contact] = time.perf_counter() - start
        plain, held = runs[False], runs[True]
        took = held.contact
        assert took is not None
        print(f"\n{sex}, {name} at {rate:g} frames/s ({len(plain.times)} frames)\n")
        lines = [line_change(plain, plain.skinned_skin, line), line_change(plain, plain.skin, line),
                 line_change(held, held.skin, line)]
        print(f"| t s | new crossing pairs | inside | with contact: pairs | inside | free vertices | Newton its | "
              f"min gap mm | contact s | {line} % skinning / without / with contact |")
        print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|")
        for k, t in enumerate(plain.times):
            row = [len(crossing_pairs(plain.skin[k], body.faces) - rest), len(test.penetrations(plain.skin[k])),
                   len(crossing_pairs(held.skin[k], body.faces) - rest), len(test.penetrations(held.skin[k]))]
            print(f"| {t:.2f} | " + " | ".join(map(str, row)) + f" | {took.free[k]} | {took.iterations[k]} | "
                  f"{took.min_distance[k] * 1e3:.2f} | {took.seconds[k]:.2f} | "
                  + " / ".join(f"{c[k]:+.1f}" for c in lines) + " |")
        for label, motion in (("without", plain), ("with", held)):
            worst = surface_integrity(body.vertices, body.faces, motion.skin, motion.times, motion.skinned_skin).worst()
            print(f"\n{label} contact: skin problems {surface_problems(worst) or 'none'}; "
                  f"largest elastic jump {worst['largest_elastic_jump_speed_m_s']:.2f} m/s")
        busy = took.free > 0
        print(f"\nwhole motion: {seconds[False]:.1f} s without contact, {seconds[True]:.1f} s with "
              f"(contact {took.seconds.sum():.1f} s: {took.seconds[busy].mean():.2f} s a frame where skin meets, "
              f"{busy.sum()} of {len(busy)} frames, {took.seconds[~busy].mean() if (~busy).any() else 0:.3f} s "
              f"elsewhere; restarts from rest after the first frame: {int(took.from_rest[1:].sum())})")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("sexes", nargs="*", default=["female", "male"])
    parser.add_argument("--rate", type=float, default=5.0, help="frames per second")
    parser.add_argument("--scenario", default="elbow_flexion_body", help="a shipped scenario's name")
    parser.add_argument("--line", default="elbow_anterior", help="a line drawn on the skin (measure.body_lines)")
    args = parser.parse_args()
    main(args.sexes, args.rate, args.scenario, args.line)
