"""CLI benchmark: each command's wall time on the default body, with its ratio to the c7f1e03 tree.

Goals (issue 14): `hitogata --help` ≤ 0.5 s, `body` ≤ 1.5 s, `measure` of a
body file with its picture ≤ 2 s. The baseline is the same command run from
the tree before issue 14 (commit c7f1e03), checked out into a temporary git
worktree and put first on PYTHONPATH, in the same run, alternating with ours
so that the machine's load falls on both alike.

Run:  python benchmarks/bench_cli.py [--repeat N]
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
BASELINE = "c7f1e03"
COMMANDS = {
    "--help": ["--help"],
    "body": ["body", "--out", "{work}/body.glb"],
    "measure body.glb (+ picture)": ["measure", "{work}/ref.glb", "--out", "{work}/report"],
}


def wall_time(src: Path, argv: list[str], work: Path) -> float:
    """Seconds one `hitogata` command takes from a fresh interpreter, with `src` first on the path."""
    for leftover in ("body.glb", "report"):
        target = work / leftover
        shutil.rmtree(target, ignore_errors=True) if target.is_dir() else target.unlink(missing_ok=True)
    env = {**os.environ, "PYTHONPATH": str(src)}
    args = [a.format(work=work) for a in argv]
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "hitogata.cli", *args], env=env, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    repeat = parser.parse_args().repeat
    with tempfile.TemporaryDirectory() as scratch:
        base, work = Path(scratch) / "base", Path(scratch) / "work"
        work.mkdir()
        subprocess.run(["git", "-C", str(REPO), "worktree", "add", "--detach", str(base), BASELINE], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            env = {**os.environ, "PYTHONPATH": str(REPO / "src")}
            subprocess.run([sys.executable, "-m", "hitogata.cli", "body", "--out", str(work / "ref.glb")],
                           env=env, check=True, stdout=subprocess.DEVNULL)
            print(f"{'command':32s} {'ours':>8s} {BASELINE:>8s}  ratio")
            for label, argv in COMMANDS.items():
                ours, theirs = [], []
                for _ in range(repeat):  # alternate, so both see the same load
                    ours.append(wall_time(REPO / "src", argv, work))
                    theirs.append(wall_time(base / "src", argv, work))
                a, b = statistics.median(ours), statistics.median(theirs)
                print(f"{label:32s} {a:7.2f}s {b:7.2f}s  {a / b:5.2f}")
        finally:
            subprocess.run(["git", "-C", str(REPO), "worktree", "remove", "--force", str(base)], check=False)


if __name__ == "__main__":
    main()
