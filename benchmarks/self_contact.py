"""The skin passing through itself at the extreme poses of issue 12: by skinning, by the elastic body, and
by the elastic body with its self-contact resolved (`elastic_pose(..., contact=True)`: the barrier of
`hitogata.geometry.barrier_contact`, IPC), and what contact costs.

For each body and pose (`hitogata.skeleton.extreme_poses`), on the coarse skin: new self-crossing triangle pairs
beyond the rest body's (`geometry.self_intersections`), skin vertices inside another part and the deepest
in mm (`geometry.contact.SelfContact`, to 25 mm), the enclosed volume against rest; the elastic pose's time
without and with contact (each the median of `REPEATS` runs, the two alternating) and their ratio (the median
of each run's pair's ratio, so a busy machine's load weighs on both alike), and all the poses' times together; for
the contact: the free skin (vertices), Newton iterations per step of the path, the smallest gap left
between skin that may meet. Prints a Markdown table (docs/elastic.md).

    PYTHONPATH=src python benchmarks/self_contact.py [female|male ...] [--poses "elbow 150°,knee 135°"]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from hitogata.body import default_body
from hitogata.skin.contact import skin_contact
from hitogata.skin.single_pose import elastic_dynamics, elastic_pose
from hitogata.geometry import enclosed_volume, self_intersections
from hitogata.skeleton.extreme_poses import extreme_poses


REPEATS = 5  # runs of each pose without and with contact, alternating; the median time of each


def crossing_pairs(v: np.ndarray, faces: np.ndarray) -> set[tuple[int, int]]:
    return set(map(tuple, self_intersections(v, faces).tolist()))


def main(sexes: list[str], names: list[str] | None) -> None:
    print("| body | pose | surface | new crossing pairs | vertices inside | deepest mm | volume | time s | ratio | "
          "free vertices | Newton its | min gap mm |")
    print("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---|---:|")
    for sex in sexes:
        body = default_body(sex)
        dynamics = elastic_dynamics(body)
        test = skin_contact(dynamics.poser)
        rest = crossing_pairs(body.vertices, body.faces)
        rest_volume = enclosed_volume(body.vertices, body.faces)
        ratios, totals = [], np.zeros(2)
        for pose, clinical in extreme_poses(dynamics.poser.skeleton).items():
            if names and pose not in names:
                continue
            times: dict[bool, list[float]] = {False: [], True: []}
            posed = {}
            for _ in range(REPEATS):
                for contact in (False, True):
                    start = time.perf_counter()
                    posed[contact] = elastic_pose(dynamics, clinical=clinical, contact=contact)
                    times[contact].append(time.perf_counter() - start)
            plain, held = posed[False], posed[True]
            t_plain, t_held = (float(np.median(times[c])) for c in (False, True))
            # each run's pair back to back, the median of their ratios: a load that drifts between runs weighs
            # on both of a pair alike
            ratios.append(float(np.median(np.array(times[True]) / np.array(times[False]))))
            totals += (t_plain, t_held)
            rows = {"DQS": (plain.skinned, ""), "elastic": (plain.vertices, f"{t_plain:.2f}"),
                    "elastic + contact": (held.vertices, f"{t_held:.2f}")}
            for name, (v, spent) in rows.items():
                inside = test.penetrations(v)
                pairs = len(crossing_pairs(v, body.faces) - rest)
                volume = enclosed_volume(v, body.faces) / rest_volume - 1.0
                extra = "| | | | |"
                if name == "elastic + contact" and held.barrier is not None:
                    b = held.barrier
                    extra = (f"| {ratios[-1]:.2f} | {int(b.free.sum())} | {','.join(map(str, b.iterations))} | "
                             f"{b.min_distance * 1e3:.2f} |")
                print(f"| {sex} | {pose} | {name} | {pairs} | {len(inside)} | {inside.deepest * 1e3:.1f} | "
                      f"{volume * 100:+.2f}% | {spent} {extra}", flush=True)
        print(f"<!-- {sex}: elastic + contact costs {min(ratios):.2f}-{max(ratios):.2f}x the elastic pose; all the poses "
              f"together {totals[1]:.1f} s against {totals[0]:.1f} s, {totals[1] / totals[0]:.2f}x -->", flush=True)


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("sexes", nargs="*", default=["female", "male"])
    parser.add_argument("--poses", default=None, help="comma-separated pose names; default all")
    args = parser.parse_args()
    main(args.sexes, args.poses.split(",") if args.poses else None)
