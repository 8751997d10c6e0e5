"""Population-study benchmark: throughput with 1 and 2 Dask workers against a plain loop.

The same study for all three: bodies of the shipped example (ANSUR II sample, half women, half
men) × its two motions (arms raised, sitting), posing by skinning, the example's 9 frames.
Baseline, measured in the same run: the tasks one by one in a plain loop in this process
(body-independent data loaded before the clock starts, as a worker's plugin does).

Goals (issue 17): 2 workers ≥ 1.7 × the throughput of 1 on this 2-core machine; per-task
overhead (a worker's wall time not spent inside tasks, per task) ≤ 10 % of a task's time.

    PYTHONPATH=src python benchmarks/bench_study.py [bodies=12]
"""

from __future__ import annotations

import os
import resource
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import dask

from hitogata.study.runner import local_cluster, plan, run_on_client, run_serial
from hitogata.study.sampling import SEXES
from hitogata.study.spec import load_study
from hitogata.study.tasks import warm

EXAMPLE = Path(__file__).parents[1] / "src" / "hitogata" / "data" / "studies" / "example.toml"
MEMORY_LIMIT = "2GiB"


def peak_rss_gib() -> float:
    """This process's peak resident memory (Linux reports KiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20


def study(bodies: int):
    spec = load_study(EXAMPLE)
    chosen = tuple(b for sex in SEXES for b in [x for x in spec.bodies if x.sex == sex][: bodies // 2])
    return replace(spec, bodies=chosen)


def on_cluster(spec, workers: int) -> dict:
    with dask.config.set({"distributed.comm.timeouts.connect": "300s"}):
        start = time.perf_counter()
        cluster, client = local_cluster(workers, MEMORY_LIMIT, dashboard=None)
        started = time.perf_counter() - start
        try:
            with tempfile.TemporaryDirectory() as out:
                s = run_on_client(spec, out, client)
            memory = client.run(peak_rss_gib)
        finally:
            client.close()
            cluster.close()
    n = s.done + s.failed
    overhead = (s.wall_seconds * workers - s.task_seconds) / n
    return {"summary": s, "start": started, "memory": sorted(memory.values()), "overhead": overhead,
            "task": s.task_seconds / n, "cpu": s.task_cpu_seconds / n}


def main() -> None:
    bodies = int(sys.argv[1]) if len(sys.argv) > 1 else 12
    spec = study(bodies)
    n = len(plan(spec))
    print(f"study: {len(spec.bodies)} bodies × {len(spec.motions)} motions = {n} tasks, posing by "
          f"{spec.model.posing} ({spec.model.skinning}), {spec.model.frames} frames; load average "
          f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    warm()
    with tempfile.TemporaryDirectory() as out:
        serial = run_serial(spec, out)
    per_task, cpu = serial.task_seconds / n, serial.task_cpu_seconds / n
    print(f"serial loop (baseline): {serial.wall_seconds:.1f} s, {serial.rate_per_minute:.1f} tasks/min, "
          f"{per_task:.2f} s per task ({cpu:.2f} s CPU), peak memory {peak_rss_gib():.2f} GiB")
    results = {}
    for workers in (1, 2):
        r = results[workers] = on_cluster(spec, workers)
        s = r["summary"]
        print(f"{workers} worker{'s' if workers > 1 else ' '}: {s.wall_seconds:.1f} s, {s.rate_per_minute:.1f} tasks/min "
              f"(cluster start {r['start']:.1f} s, not counted), {r['task']:.2f} s per task inside "
              f"({r['cpu']:.2f} s CPU: {100 * r['cpu'] / r['task']:.0f} % of a core), overhead "
              f"{r['overhead']:.3f} s per task = {100 * r['overhead'] / r['task']:.1f} % of a task (goal ≤ 10 %), "
              f"peak memory per worker {', '.join(f'{m:.2f}' for m in r['memory'])} GiB (limit {MEMORY_LIMIT})")
    ratio = results[2]["summary"].rate_per_minute / results[1]["summary"].rate_per_minute
    print(f"2 workers / 1 worker: {ratio:.2f}× (goal ≥ 1.7×); 1 worker / serial loop: "
          f"{results[1]['summary'].rate_per_minute / serial.rate_per_minute:.2f}×")
    both = results[2]
    print(f"with a free core per worker, 2 workers would give {2 * 60 / (both['cpu'] + both['overhead']):.1f} "
          f"tasks/min (CPU per task + overhead); this run's CPU share shows how far the machine is from that")
    print(f"10,000 bodies × {len(spec.motions)} motions at {cpu:.2f} CPU s per task: "
          f"{10_000 * len(spec.motions) * cpu / 3600:.1f} core-hours")


if __name__ == "__main__":
    main()
