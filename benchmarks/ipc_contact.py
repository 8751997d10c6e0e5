"""The skin's self-contact as a barrier problem (`hitogata.geometry.barrier_contact`, IPC) at the deep
poses of issue 12, against the elastic pose without contact: what it leaves and what it costs.

For each body and pose, on the coarse skin: new self-crossing triangle pairs beyond the rest body's
(`geometry.self_intersections`) before (elastic pose) and after the barrier pass; skin vertices inside
another part and the deepest (`geometry.contact.SelfContact`, to 25 mm); enclosed volume against rest;
the elastic pose's time, the barrier pass's time (its path of skinned postures included) and the ratio
(elastic + barrier) / elastic, measured in this run (`hitogata.dynamics.barrier_pose.barrier_skin`: the
path is the rest skin, the skinned skin at STEPS fractions of the pose's joint angles, the elastic skin).

    PYTHONPATH=src python benchmarks/ipc_contact.py [female|male ...] [--poses "elbow 150°,knee 135°"]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from skin_stretch_lines import poses

from hitogata.body import default_body
from hitogata.dynamics.barrier_pose import barrier_skin
from hitogata.dynamics.single_pose import elastic_dynamics, elastic_pose
from hitogata.geometry import enclosed_volume, self_intersections

DEEP = ("elbow 150°", "knee 135°", "hip flexion 120°", "seated 90/90", "hip adduction 30°")


def new_pairs(v: np.ndarray, faces: np.ndarray, rest: set[tuple[int, int]]) -> int:
    return sum(1 for p in map(tuple, self_intersections(v, faces).tolist()) if p not in rest)


def main(sexes: list[str], names: list[str]) -> None:
    print("| body | pose | crossings elastic | crossings barrier | inside | deepest mm | volume elastic | volume | "
          "elastic s | barrier s | ratio | free vertices | Newton its | min gap mm |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|")
    for sex in sexes:
        body = default_body(sex)
        dynamics = elastic_dynamics(body)
        test = dynamics.contact
        rest = set(map(tuple, self_intersections(body.vertices, body.faces).tolist()))
        rest_volume = enclosed_volume(body.vertices, body.faces)
        all_poses = poses(dynamics.poser.skeleton)
        for name in names:
            clinical = all_poses[name]
            start = time.perf_counter()
            plain = elastic_pose(dynamics, clinical=clinical)
            t_elastic = time.perf_counter() - start
            start = time.perf_counter()
            result = barrier_skin(plain)
            t_barrier = time.perf_counter() - start
            v = result.vertices
            inside = test.penetrations(v)
            volume = enclosed_volume(v, body.faces) / rest_volume - 1.0
            before = enclosed_volume(plain.vertices, body.faces) / rest_volume - 1.0
            print(f"| {sex} | {name} | {new_pairs(plain.vertices, body.faces, rest)} | "
                  f"{new_pairs(v, body.faces, rest)} | {len(inside)} | {inside.deepest * 1e3:.1f} | "
                  f"{before * 100:+.2f}% | {volume * 100:+.2f}% | {t_elastic:.2f} | {t_barrier:.2f} | "
                  f"{(t_elastic + t_barrier) / t_elastic:.2f} | {result.free.sum()} | "
                  f"{','.join(map(str, result.iterations))} | {result.min_distance * 1e3:.2f} |", flush=True)


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("sexes", nargs="*", default=["female", "male"])
    parser.add_argument("--poses", default=",".join(DEEP))
    args = parser.parse_args()
    main(args.sexes, args.poses.split(","))
