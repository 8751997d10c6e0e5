"""Dynamics timings: the per-frame elastic update and the demo, each against a baseline of the same run.

Default model: the default female body's trunk, P2 tets at the elastic model's
default size, 40 modes. A frame of the paper's experiment (the rectus
abdominis stretched) is prepared once; then

- per-frame elastic update (what every output frame costs after
  precomputation): modal superposition Φ (q − s) in float32, the node
  rotations, the skin map, and the skin's own DQS — against two baselines on
  the same frame: a full-mesh linear static solve K u = f with K prefactored,
  and the same superposition in float64 with the modes expanded to all dofs;
- quasi-static per pose (rotation-aware, warm-started, the work a new pose
  costs before its frames) against one cold start;
- the demo (`run_demo`: model, both experiments, files) wall time, against
  the extra cost its frames would have with the quasi-statics cold-started
  at every frame (the per-pose figures above times its frame count).

Run:  python benchmarks/bench_dynamics.py [--repeat 50] [--no-demo]
"""

from __future__ import annotations

import argparse
import tempfile
import time

import numpy as np

from hitogata.body import default_body
from hitogata.dynamics import BodyDynamics
from hitogata.dynamics.demo import DEMO_RATE, EXPERIMENTS, run_demo
from hitogata.dynamics.scenario import load_scenario, shipped_scenarios
from hitogata.elastic import build_elastic_model
from hitogata.fem.verify import StaticSolver


def best(fn, repeat: int) -> float:
    """Best wall time of `repeat` calls, ms."""
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return 1e3 * min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=50)
    parser.add_argument("--no-demo", action="store_true")
    args = parser.parse_args()

    body = default_body("female")
    start = time.perf_counter()
    model = build_elastic_model(body)
    dyn = BodyDynamics.build(body, model)
    precompute = time.perf_counter() - start
    n, k, v = len(model.points), dyn.vectors32.shape[1], len(body.vertices)
    print(f"default model: trunk {model.element}, {len(model.elements)} elements, {n} nodes, {k} modes, "
          f"{v} skin vertices; built and precomputed in {precompute:.1f} s")

    angles = dyn.poser.angles(contractions={"rectus_abdominis_l": -0.08}, on_limit="clamp")
    pose = dyn.poser.kinematics.pose(angles)
    g, R = dyn.rig.pose(pose.rotations, pose.translations)
    g, R = g[0], R[0]
    loads = dyn.loads(R, {"rectus_abdominis_l": -0.08}, gravity=True)
    delta, _ = dyn.quasi_static(g, R, loads, None, 40)
    dynamic = np.random.default_rng(0).normal(size=k) * 1e-3
    rot, tra = pose.rotations[0], pose.translations[0]

    update = best(lambda: dyn.frame(rot, tra, R, delta, dynamic), args.repeat)
    phi32, R32, d32 = dyn.vectors32, R.astype(np.float32), delta.astype(np.float32)
    modal32 = best(lambda: np.einsum("nij,nj->ni", R32, d32 + (phi32 @ dynamic.astype(np.float32)).reshape(-1, 3)),
                   args.repeat)
    phi64 = model.modes.vectors
    modal64 = best(lambda: np.einsum("nij,nj->ni", R, delta + (phi64 @ dynamic).reshape(-1, 3)), args.repeat)
    solver = StaticSolver(model.K, fixed_nodes=model.fixed_nodes)
    force = model.muscle_load("rectus_abdominis", -0.08)
    linear = best(lambda: solver.solve(force), max(3, args.repeat // 10))
    print(f"per-frame elastic update: {update:.2f} ms  (goal <= 5 ms): of which u = R (δ + Φ (q − s)) on all "
          f"nodes {modal32:.2f} ms, the rest the skin's DQS and the node-to-skin map")
    print(f"  baseline, full-mesh linear solve K u = f (prefactored, {3 * n} dofs): {linear:.1f} ms "
          f"({linear / update:.0f}x the whole update)")
    print(f"  baseline, the superposition in float64: {modal64:.2f} ms ({modal64 / modal32:.1f}x float32)")

    warm = best(lambda: dyn.quasi_static(g, R, loads, delta, 6), 5)
    cold = best(lambda: dyn.quasi_static(g, R, loads, None, 40), 2)
    print(f"quasi-statics per new pose (warm-started, <= 6 local/global steps): {warm:.0f} ms; "
          f"cold start (40 steps): {cold:.0f} ms")

    if args.no_demo:
        return
    with tempfile.TemporaryDirectory() as out:
        start = time.perf_counter()
        run_demo(out)
        wall = time.perf_counter() - start
    shipped = shipped_scenarios()
    frames = sum(int(round(load_scenario(shipped[f]).duration * DEMO_RATE)) + 1 for _, f in EXPERIMENTS)
    print(f"demo (dynamics part): {wall:.1f} s wall  (goal <= 60 s)")
    print(f"  baseline, the quasi-statics cold-started at every one of its {frames} frames instead of warm: "
          f"+{frames * (cold - warm) / 1e3:.1f} s")


if __name__ == "__main__":
    main()
