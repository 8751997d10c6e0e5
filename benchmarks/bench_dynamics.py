"""Dynamics timings on the whole default body, each against today's path (commit c7f1e03) in the same run.

Model: the default female body, `extent="body"`, P2 at the elastic model's
default size, 40 modes. A pose sequence (both elbows bent from rest to 140°
in 26 frames, then a trunk flexion to 70 % of its range with the arms raised
forward to 110°, 20 frames) is solved

- warm: each pose from the previous pose's answer (positions and rotations:
  what `simulate` does, at its `ITERATIONS` steps), per pose;
- cold: single poses from rest to convergence (40 steps),

by the current quasi-statics and by those of commit c7f1e03 (`git show`
of `dynamics/quasistatic.py`, `rotations.py`, `untangle.py`, run on the
same model through `BodyDynamics.build(solver=...)`), with the largest
difference of their answers in mm. Then the per-frame elastic update, and
the demo (`run_demo`: model, both experiments, files) against the demo of
commit c7f1e03 run from a `git archive` of it in a subprocess (on the
trunk: the body the demo ran on then).

Timings are wall-clock on a shared machine: the load (`os.getloadavg`) is
printed with them; the per-pose figures are also given as CPU time of this
process (BLAS on one thread in the new path, so CPU time is its work).

Run:  python benchmarks/bench_dynamics.py [--repeat 3] [--no-demo] [--no-baseline-demo]
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
import types
from pathlib import Path

import numpy as np

from hitogata.body import default_body
from hitogata.dynamics import BodyDynamics
from hitogata.dynamics.motion import ITERATIONS
from hitogata.elastic import build_elastic_model

BASELINE = "c7f1e03"
ROOT = Path(__file__).resolve().parents[1]
RECORDED = {  # c7f1e03 on this machine, for when git cannot give the old sources
    "warm_ms": 556.0, "cold_ms": 2518.0, "demo_s": 70.0,
}
TRUNK = [f"lumbar_{i}" for i in range(1, 6)] + [f"thoracic_{i}" for i in range(1, 13)]


def load() -> str:
    one, five, _ = os.getloadavg()
    return f"load {one:.1f} (5 min {five:.1f}) on {os.cpu_count()} cores"


def baseline_solver() -> type | None:
    """The quasi-statics of commit BASELINE as a class usable by `BodyDynamics.build`, or None."""
    package = types.ModuleType("baseline_dynamics")
    sys.modules["baseline_dynamics"] = package
    try:
        for name in ("rotations", "untangle", "quasistatic"):
            source = subprocess.run(["git", "show", f"{BASELINE}:src/hitogata/dynamics/{name}.py"], cwd=ROOT,
                                    capture_output=True, text=True, check=True).stdout
            source = source.replace("from hitogata.dynamics.", "from baseline_dynamics.")
            module = types.ModuleType(f"baseline_dynamics.{name}")
            exec(compile(source, f"{BASELINE}:{name}.py", "exec"), module.__dict__)
            sys.modules[module.__name__] = module
            setattr(package, name, module)
    except (OSError, subprocess.CalledProcessError, ImportError, SyntaxError) as exc:
        print(f"  (the solver of {BASELINE} could not be loaded: {exc}; recorded figures used)")
        return None
    old = package.quasistatic.QuasiStatic

    class Baseline(old):
        """c7f1e03's solver: its rotations' warm start lives in the object (reset for a cold start)."""

        def warm_start(self) -> None:
            self.quaternions[:] = (1.0, 0.0, 0.0, 0.0)

        def solve(self, x, loads=None, iterations=8, tolerance=1e-5, warm=None):
            return old.solve(self, x, loads, iterations, tolerance)

    return Baseline


def poses(skeleton) -> list[np.ndarray]:
    """The sequence: elbows 26 frames, then trunk flexion with the arms raised, 20 frames."""
    def clinical(values: dict[str, float]) -> np.ndarray:
        q = np.zeros(skeleton.n_dofs)
        for name, degrees in values.items():
            k = skeleton.dof_index(name)
            q[k] = np.radians(degrees) - skeleton.rest[k]
        return np.clip(q, skeleton.lower, skeleton.upper)

    elbow = np.degrees(skeleton.rest[skeleton.dof_index("forearm_l.flexion")])
    out = [clinical({f"forearm_{s}.flexion": elbow + (140 - elbow) * i / 25 for s in "lr"}) for i in range(26)]
    for i in range(1, 21):
        q = clinical({f"upper_arm_{s}.flexion": 110 * i / 20 for s in "lr"})
        for part in TRUNK:
            k = skeleton.dof_index(f"{part}.flexion")
            q[k] = skeleton.upper[k] * 0.7 * i / 20
        out.append(q)
    return out


def sequence(dyn: BodyDynamics, frames: list) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Warm-started solves along the frames: answers (F, N, 3), wall and CPU seconds per pose."""
    warm = dyn.statics.warm_start()
    delta, answers, wall, cpu = None, [], [], []
    for g, R, loads in frames:
        start, start_cpu = time.perf_counter(), time.process_time()
        delta, _ = dyn.quasi_static(g, R, loads, delta, ITERATIONS, warm)
        wall.append(time.perf_counter() - start)
        cpu.append(time.process_time() - start_cpu)
        answers.append(delta)
    return np.array(answers), np.array(wall), np.array(cpu)


def cold(dyn: BodyDynamics, frame, repeat: int) -> tuple[np.ndarray, float, float]:
    """A pose solved from rest (40 steps): answer, best wall and CPU seconds."""
    g, R, loads = frame
    best_wall = best_cpu = np.inf
    for _ in range(repeat):
        warm = dyn.statics.warm_start()
        start, start_cpu = time.perf_counter(), time.process_time()
        delta, _ = dyn.quasi_static(g, R, loads, None, 40, warm)
        best_wall = min(best_wall, time.perf_counter() - start)
        best_cpu = min(best_cpu, time.process_time() - start_cpu)
    return delta, best_wall, best_cpu


def quasi_statics(body, model, repeat: int) -> None:
    new = BodyDynamics.build(body, model)
    frames = []
    for q in poses(new.poser.skeleton):
        pose = new.poser.kinematics.pose(q)
        g, R = new.rig.pose(pose.rotations, pose.translations)
        frames.append((g[0], R[0], new.loads(R[0], {}, gravity=True)))
    answers, wall, cpu = sequence(new, frames)
    print(f"quasi-statics, warm-started, per pose ({len(frames) - 1} poses after the first; {load()}):")
    print(f"  new: wall mean {1e3 * wall[1:].mean():.0f} ms, median {1e3 * np.median(wall[1:]):.0f} ms, "
          f"max {1e3 * wall[1:].max():.0f} ms; CPU mean {1e3 * cpu[1:].mean():.0f} ms  (goal <= 100 ms)")
    picks = (12, 25, len(frames) - 1)
    cold_new = [cold(new, frames[i], repeat) for i in picks]
    Baseline = baseline_solver()
    if Baseline is None:
        print(f"  {BASELINE} (recorded): wall mean {RECORDED['warm_ms']:.0f} ms "
              f"({RECORDED['warm_ms'] / (1e3 * wall[1:].mean()):.1f}x the new)")
    else:
        old = BodyDynamics.build(body, model, solver=Baseline)
        old_answers, old_wall, old_cpu = sequence(old, frames)
        print(f"  {BASELINE}: wall mean {1e3 * old_wall[1:].mean():.0f} ms, median "
              f"{1e3 * np.median(old_wall[1:]):.0f} ms, max {1e3 * old_wall[1:].max():.0f} ms; CPU mean "
              f"{1e3 * old_cpu[1:].mean():.0f} ms (BLAS on 2 threads)")
        print(f"  ratio {BASELINE} / new: wall {old_wall[1:].mean() / wall[1:].mean():.1f}x, "
              f"CPU {old_cpu[1:].mean() / cpu[1:].mean():.1f}x; largest difference of the answers "
              f"{1e6 * np.linalg.norm(old_answers - answers, axis=2).max():.3f} µm")
    print(f"quasi-statics from rest, 40 steps, best of {repeat} ({load()}):")
    for i, (delta, w, c) in zip(picks, cold_new):
        line = f"  pose {i}: new {1e3 * w:.0f} ms wall, {1e3 * c:.0f} ms CPU (goal <= 1 s)"
        if Baseline is not None:
            old_delta, old_w, old_c = cold(old, frames[i], 1)
            line += (f"; {BASELINE} {1e3 * old_w:.0f} ms wall ({old_w / w:.1f}x), {1e3 * old_c:.0f} ms CPU; "
                     f"difference {1e6 * np.linalg.norm(old_delta - delta, axis=1).max():.3f} µm")
        print(line)
    update(new, frames[-1], answers[-1], max(20, 10 * repeat))


def update(dyn: BodyDynamics, frame, delta: np.ndarray, repeat: int) -> None:
    """The per-frame elastic update (superposition, node rotations, skin map, the skin's own DQS)."""
    _, R, _ = frame
    q = np.zeros(dyn.poser.skeleton.n_dofs)
    pose = dyn.poser.kinematics.pose(q)
    rot, tra = pose.rotations[0], pose.translations[0]
    dynamic = np.random.default_rng(0).normal(size=dyn.vectors32.shape[1]) * 1e-3
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        dyn.frame(rot, tra, R, delta, dynamic)
        times.append(time.perf_counter() - start)
    print(f"per-frame elastic update: best {1e3 * min(times):.2f} ms, median {1e3 * np.median(times):.2f} ms "
          f"({len(dyn.model.points)} nodes, {dyn.vectors32.shape[1]} modes; the same code as {BASELINE}: ratio 1)")


def demo_times(out: Path) -> dict[str, float]:
    """Seconds of the demo's parts (model, simulation, checks, files: what its summaries list), summed
    over its experiments' summaries."""
    split: dict[str, float] = {}
    for path in sorted((out / "dynamics").glob("*_summary.json")):
        for key, value in json.loads(path.read_text())["seconds"].items():
            split[key] = split.get(key, 0.0) + value
    return split


def demo(baseline: bool) -> None:
    from hitogata.simulation.demo import run_demo

    with tempfile.TemporaryDirectory() as out:
        start, start_cpu = time.perf_counter(), time.process_time()
        run_demo(out)
        wall, cpu = time.perf_counter() - start, time.process_time() - start_cpu
        split = demo_times(Path(out))
    line = ", ".join(f"{k} {v:.1f} s" for k, v in split.items())
    print(f"demo (dynamics part): {wall:.1f} s wall, {cpu:.1f} s CPU ({line}; {load()})  (goal <= 60 s)")
    if not baseline:
        return
    with tempfile.TemporaryDirectory() as tree:
        try:
            archive = subprocess.run(["git", "archive", BASELINE, "src"], cwd=ROOT, capture_output=True, check=True)
            subprocess.run(["tar", "-x", "-C", tree], input=archive.stdout, check=True)
        except (OSError, subprocess.CalledProcessError):
            print(f"  {BASELINE} (recorded): {RECORDED['demo_s']:.0f} s on an idle machine "
                  f"({RECORDED['demo_s'] / wall:.1f}x the new)")
            return
        out = Path(tree) / "out"
        code = "import sys; from hitogata.simulation.demo import run_demo; run_demo(sys.argv[1])"
        start, children = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN)
        subprocess.run([sys.executable, "-c", code, str(out)], env={**os.environ, "PYTHONPATH": f"{tree}/src"},
                       check=True)
        old_wall = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        old_cpu = after.ru_utime + after.ru_stime - children.ru_utime - children.ru_stime
        old_split = demo_times(out)
    line = ", ".join(f"{k} {v:.1f} s" for k, v in old_split.items())
    print(f"  {BASELINE}'s demo (its trunk model): {old_wall:.1f} s wall, {old_cpu:.1f} s CPU ({line}; {load()}); "
          f"ratio {BASELINE} / new {old_wall / wall:.2f}x wall, {old_cpu / cpu:.2f}x CPU")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="cold solves per pose (best taken)")
    parser.add_argument("--no-demo", action="store_true")
    parser.add_argument("--no-baseline-demo", action="store_true", help=f"skip running {BASELINE}'s demo")
    args = parser.parse_args()

    body = default_body("female")
    start = time.perf_counter()
    model = build_elastic_model(body, extent="body")
    print(f"whole default female body: {model.element}, {len(model.elements)} elements, {len(model.points)} nodes, "
          f"{len(model.modes.eigenvalues)} modes; built in {time.perf_counter() - start:.1f} s ({load()})")
    quasi_statics(body, model, args.repeat)
    if not args.no_demo:
        demo(not args.no_baseline_demo)


if __name__ == "__main__":
    main()
