"""The elastic answer's speed: a held pose on the command line, cold and with its model cached, and a warm
elastic posture with contact in the library, each beside a baseline tree's in the same run (default: the commit
where this branch left main, so that the skins compared differ by this branch's changes only).

1. `hitogata pose --elastic --contact --skinning dqs --angle knee_r.flexion=135deg --out x.ply`: the
   baseline tree's run (it builds the whole-body model every time, or reads its own cache if it has one:
   it is given an empty one), ours on an empty cache (cold: builds and stores the model), ours again
   (warm: reads it). Goals: warm ≤ 3 s wall on two cores and ≥ 8x faster than the baseline, cold ≤ 15 s.
2. In one process per tree: the model made (ours: read from the cache the first part filled), then
   `elastic_pose(..., contact=True)` at each of the first N extreme poses of `benchmarks/self_contact.py`
   (`hitogata.skeleton.extreme_poses`). Goal: median ≤ 1 s.

Each prints wall and CPU seconds (user + system: it wanders far less with the machine's load) and the ratios,
and the largest distance between our skin and the baseline's at each posture (the same answers: ≤ 0.1 mm).

Run:  nice -n 5 python benchmarks/bench_elastic_cache.py [--baseline COMMIT] [--poses N]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from timing import timed_process

REPO = Path(__file__).resolve().parents[1]
POSE = ["pose", "--elastic", "--contact", "--skinning", "dqs", "--angle", "knee_r.flexion=135deg", "--force"]
GOALS = {"warm": 3.0, "cold": 15.0, "speedup": 8.0, "library": 1.0}  # s, s, x, s

LIBRARY = """
import json, sys, time
import numpy as np
from hitogata.body import default_body
from hitogata.skin.single_pose import elastic_dynamics, elastic_pose
from hitogata.skeleton.extreme_poses import extreme_poses
count, out, sexes = int(sys.argv[1]), sys.argv[2], sys.argv[3].split(",")
rows, skins = [], {}
for sex in sexes:
    wall, cpu = time.perf_counter(), time.process_time()
    dynamics = elastic_dynamics(default_body(sex))
    rows.append({"pose": f"{sex}: model", "wall": time.perf_counter() - wall, "cpu": time.process_time() - cpu})
    for name, clinical in list(extreme_poses(dynamics.poser.skeleton).items())[:count]:
        wall, cpu = time.perf_counter(), time.process_time()
        held = elastic_pose(dynamics, clinical=clinical, contact=True)
        rows.append({"pose": f"{sex}: {name}", "wall": time.perf_counter() - wall, "cpu": time.process_time() - cpu})
        skins[f"{sex}: {name}"] = held.vertices
np.savez(out, **skins)
print(json.dumps(rows))
"""


def pose_run(src: Path, work: Path, cache: Path, name: str) -> tuple[float, float, np.ndarray]:
    """Wall and CPU seconds of the CLI's held knee pose with `src` first on the path, and its skin (V, 3)."""
    env = {**os.environ, "PYTHONPATH": str(src), "HITOGATA_CACHE": str(cache)}
    out = work / f"{name}.ply"
    wall, cpu = timed_process([sys.executable, "-m", "hitogata.cli", *POSE, "--out", str(out)], env,
                              stdout=subprocess.DEVNULL)
    import trimesh

    return wall, cpu, np.asarray(trimesh.load(out, process=False).vertices)


def library_run(src: Path, cache: Path, count: int, sexes: str, work: Path, name: str) -> tuple[list[dict], dict]:
    """The library's times (per body: its model's, then each posture's) and skins with `src` first on the path."""
    env = {**os.environ, "PYTHONPATH": str(src), "HITOGATA_CACHE": str(cache)}
    skins = work / f"{name}.npz"
    done = subprocess.run([sys.executable, "-c", LIBRARY, str(count), str(skins), sexes], env=env, check=True,
                          capture_output=True, text=True)
    with np.load(skins) as stored:
        return json.loads(done.stdout.strip().splitlines()[-1]), {k: stored[k] for k in stored.files}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", default=None, help="the commit to compare with (default: where this branch "
                                                          "left main, so that only its own changes are compared)")
    parser.add_argument("--poses", type=int, default=10, help="extreme poses per body in the library part (default "
                                                              "all 10)")
    parser.add_argument("--sexes", default="female,male", help="bodies of the library part (default female,male)")
    args = parser.parse_args()
    if args.baseline is None:
        args.baseline = subprocess.run(["git", "-C", str(REPO), "merge-base", "HEAD", "main"], check=True,
                                       capture_output=True, text=True).stdout.strip()[:10]
    with tempfile.TemporaryDirectory() as scratch:
        root = Path(scratch)
        base, work, ours_cache, base_cache = root / "base", root / "work", root / "cache", root / "base_cache"
        work.mkdir()
        subprocess.run(["git", "-C", str(REPO), "worktree", "add", "--detach", str(base), args.baseline], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs")
            print(f"\n`hitogata {' '.join(POSE)} --out x.ply`")
            b_wall, b_cpu, b_skin = pose_run(base / "src", work, base_cache, "base")
            c_wall, c_cpu, c_skin = pose_run(REPO / "src", work, ours_cache, "cold")
            w_wall, w_cpu, w_skin = pose_run(REPO / "src", work, ours_cache, "warm")
            print(f"{'run':28s} {'wall s':>7s} {'CPU s':>6s} {'wall/first':>10s} {'wall/base':>9s} {'CPU/base':>8s}")
            for label, wall, cpu in ((f"{args.baseline} (builds)", b_wall, b_cpu), ("ours, first (cold)", c_wall, c_cpu),
                                     ("ours, second (cached)", w_wall, w_cpu)):
                print(f"{label:28s} {wall:7.2f} {cpu:6.2f} {wall / c_wall:10.2f} {wall / b_wall:9.2f} {cpu / b_cpu:8.2f}")
            print(f"skin, ours against {args.baseline}: cold {np.abs(c_skin - b_skin).max() * 1e3:.4f} mm, "
                  f"cached {np.abs(w_skin - b_skin).max() * 1e3:.4f} mm at most (goal ≤ 0.1 mm)")
            print(f"goals: cached ≤ {GOALS['warm']} s wall: {'met' if w_wall <= GOALS['warm'] else 'NOT met'}; "
                  f"≥ {GOALS['speedup']:.0f}x the baseline: {b_wall / w_wall:.1f}x "
                  f"({'met' if b_wall / w_wall >= GOALS['speedup'] else 'NOT met'}); "
                  f"first ≤ {GOALS['cold']} s: {'met' if c_wall <= GOALS['cold'] else 'NOT met'}")

            print(f"\nelastic_pose(..., contact=True), the first {args.poses} extreme poses of {args.sexes}, warm "
                  "(the model: ours read from the cache where the first part stored it)")
            ours, our_skins = library_run(REPO / "src", ours_cache, args.poses, args.sexes, work, "ours")
            theirs, their_skins = library_run(base / "src", base_cache, args.poses, args.sexes, work, "theirs")
            print(f"{'pose':32s} {'wall s':>7s} {'CPU s':>6s} {'base wall':>9s} {'base CPU':>8s} {'skin Δ mm':>9s}")
            for a, b in zip(ours, theirs):
                name = a["pose"]
                gap = "" if name.endswith("model") else f"{np.abs(our_skins[name] - their_skins[name]).max() * 1e3:9.4f}"
                print(f"{name:32s} {a['wall']:7.2f} {a['cpu']:6.2f} {b['wall']:9.2f} {b['cpu']:8.2f} {gap}")
            postures = [[r for r in runs if not r["pose"].endswith("model")] for runs in (ours, theirs)]
            wall, cpu = (statistics.median(r[k] for r in postures[0]) for k in ("wall", "cpu"))
            wall_0, cpu_0 = (statistics.median(r[k] for r in postures[1]) for k in ("wall", "cpu"))
            print(f"median: {wall:.2f} s wall, {cpu:.2f} s CPU; {args.baseline} {wall_0:.2f} s, {cpu_0:.2f} s "
                  f"(ratio {wall / wall_0:.2f}, CPU {cpu / cpu_0:.2f}); goal ≤ {GOALS['library']} s: "
                  f"{'met' if wall <= GOALS['library'] else 'NOT met'}")
            print(f"load average {os.getloadavg()[0]:.1f} at the end")
        finally:
            subprocess.run(["git", "-C", str(REPO), "worktree", "remove", "--force", str(base)], check=False)


if __name__ == "__main__":
    main()
