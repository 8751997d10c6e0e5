"""`hitogata ease --surface elastic` end to end: the eight mobility motions at 5 frames/s (139 frames) on a
default body, this tree's code and a baseline commit's (default `main`), each in a fresh process with a disk
cache of its own that the run fills from empty (the whole-body model's build counted in both), in the same
run. Prints wall and CPU seconds (the command's worker processes counted) and the ratio, and per motion the
largest difference between the two runs' ease figures (cm): 0 where the code changed only speed.

    PYTHONPATH=src python benchmarks/bench_ease_elastic.py [female|male ...] [--baseline REV] [--now-only]
"""

from __future__ import annotations

import argparse
import csv
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def run(src: Path, sex: str, out: Path, cache: Path) -> tuple[float, float]:
    """Wall and CPU seconds of one `hitogata ease --surface elastic` in a fresh process on the package at src."""
    env = {**os.environ, "PYTHONPATH": str(src), "HITOGATA_CACHE": str(cache)}
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "hitogata.cli", "ease", "--sex", sex, "--surface", "elastic", "--out", str(out)],
                   check=True, env=env, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def figures(folder: Path) -> dict[tuple[str, str], tuple[float, float]]:
    """(motion, measurement) → (largest increase, largest decrease) in cm from an ease.csv; undefined ones left out."""
    found = {}
    with open(folder / "ease.csv", newline="") as f:
        for row in csv.DictReader(f):
            if row["increase_cm"] != "undefined":
                found[(row["motion"], row["measurement"])] = (float(row["increase_cm"]), float(row["decrease_cm"]))
    return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sexes", nargs="*", default=["female"], choices=["female", "male"])
    parser.add_argument("--baseline", default="main", help="the commit whose code runs as 'before' (default main)")
    parser.add_argument("--now-only", action="store_true", help="skip the baseline's run")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="hitogata-ease-bench-") as scratch_name:
        scratch = Path(scratch_name)
        baseline = None
        if not args.now_only:
            archive = subprocess.run(["git", "archive", args.baseline, "src"], cwd=ROOT, capture_output=True)
            if archive.returncode:
                print(f"{args.baseline}: not run (git archive exited {archive.returncode})")
            else:
                (scratch / "baseline").mkdir()
                subprocess.run(["tar", "-x", "-C", str(scratch / "baseline")], input=archive.stdout, check=True)
                baseline = scratch / "baseline" / "src"
        print(f"| body | {args.baseline} wall s | {args.baseline} CPU s | now wall s | now CPU s | CPU ratio "
              "| largest ease difference per motion, cm |")
        print("|---|---:|---:|---:|---:|---:|---|")
        for sex in args.sexes:
            now_wall, now_cpu = run(ROOT / "src", sex, scratch / f"now-{sex}", scratch / f"cache-now-{sex}")
            if baseline is None:
                print(f"| {sex} | — | — | {now_wall:.1f} | {now_cpu:.1f} | — | — |")
                continue
            base_wall, base_cpu = run(baseline, sex, scratch / f"base-{sex}", scratch / f"cache-base-{sex}")
            now, base = figures(scratch / f"now-{sex}"), figures(scratch / f"base-{sex}")
            differ: dict[str, float] = {}
            for key in now.keys() & base.keys():
                gap = max(abs(a - b) for a, b in zip(now[key], base[key]))
                differ[key[0]] = max(differ.get(key[0], 0.0), gap)
            listed = ", ".join(f"{motion} {gap:.2f}" for motion, gap in sorted(differ.items()))
            print(f"| {sex} | {base_wall:.1f} | {base_cpu:.1f} | {now_wall:.1f} | {now_cpu:.1f} "
                  f"| {base_cpu / now_cpu:.2f} | {listed} |")


if __name__ == "__main__":
    main()
