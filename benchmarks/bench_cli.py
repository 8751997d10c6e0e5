"""CLI benchmark: each command's wall and CPU time on the default body, with its ratio to a baseline tree.

Goals (issue 14): `hitogata --help` ≤ 0.5 s, `body` ≤ 1.5 s, `measure` of a
body file with its picture ≤ 2 s. The baseline is the same command run from
another commit's tree (default eabcd71, before the start-up and picture work
of issue 14's "speed a user feels"; c7f1e03 is the tree before issue 14),
checked out into a temporary git worktree and put first on PYTHONPATH, in the
same run, alternating with ours so that the machine's load falls on both alike.
The machine is shared, so the CPU time (user + system of the command's process)
is printed beside the wall time: it wanders far less with the load.

Run:  python benchmarks/bench_cli.py [--repeat N] [--baseline COMMIT]
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from timing import timed_process

REPO = Path(__file__).resolve().parents[1]
COMMANDS = {  # label → (arguments, goal in s)
    "--help": (["--help"], 0.5),
    "body": (["body", "--out", "{work}/body.glb"], 1.5),
    "measure body.glb (+ picture)": (["measure", "{work}/ref.glb", "--out", "{work}/report"], 2.0),
}


def timed_run(src: Path, argv: list[str], work: Path) -> tuple[float, float]:
    """Wall and CPU seconds of one `hitogata` command in a fresh interpreter, with `src` first on the path."""
    for leftover in ("body.glb", "report"):
        target = work / leftover
        shutil.rmtree(target, ignore_errors=True) if target.is_dir() else target.unlink(missing_ok=True)
    env = {**os.environ, "PYTHONPATH": str(src)}
    args = [a.format(work=work) for a in argv]
    return timed_process([sys.executable, "-m", "hitogata.cli", *args], env, stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--baseline", default="eabcd71", help="the commit to compare with (default eabcd71)")
    args = parser.parse_args()
    baseline = args.baseline
    with tempfile.TemporaryDirectory() as scratch:
        base, work = Path(scratch) / "base", Path(scratch) / "work"
        work.mkdir()
        subprocess.run(["git", "-C", str(REPO), "worktree", "add", "--detach", str(base), baseline], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            env = {**os.environ, "PYTHONPATH": str(REPO / "src")}
            subprocess.run([sys.executable, "-m", "hitogata.cli", "body", "--out", str(work / "ref.glb")],
                           env=env, check=True, stdout=subprocess.DEVNULL)
            print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs; medians of {args.repeat} runs")
            print(f"{'command':30s} {'wall':>7s} {baseline:>8s} {'ratio':>6s}   {'CPU':>6s} {baseline:>8s} "
                  f"{'ratio':>6s}  goal (wall)")
            for label, (argv, goal) in COMMANDS.items():
                ours, theirs = [], []
                for _ in range(args.repeat):  # alternate, so both see the same load
                    ours.append(timed_run(REPO / "src", argv, work))
                    theirs.append(timed_run(base / "src", argv, work))
                (wall, cpu), (wall_0, cpu_0) = ([statistics.median(t) for t in zip(*runs)] for runs in (ours, theirs))
                verdict = "met" if wall <= goal else "NOT met"
                print(f"{label:30s} {wall:6.2f}s {wall_0:7.2f}s {wall / wall_0:6.2f}   {cpu:5.2f}s {cpu_0:7.2f}s "
                      f"{cpu / cpu_0:6.2f}  ≤ {goal} s: {verdict}")
            print(f"load average {os.getloadavg()[0]:.1f} at the end")
        finally:
            subprocess.run(["git", "-C", str(REPO), "worktree", "remove", "--force", str(base)], check=False)


if __name__ == "__main__":
    main()
