"""`hitogata validate` on the shipped validation set and `hitogata identify` on its real rows: wall and CPU time.

The goals: the whole table within 20 minutes on 2 cores, the identification within 10. Each is run as a user
runs it (the command, a fresh process), against the cost of building one body in the same run as the baseline
(`hitogata body`), so a busy machine shows as a slower baseline too. The figures are written to
benchmarks/results/validation.json.

    python benchmarks/bench_validation.py [--skip-validate] [--skip-identify]
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

RESULTS = Path(__file__).parent / "results" / "validation.json"


def run(args: list[str]) -> tuple[float, float, str]:
    """Wall and CPU seconds (the child's) of one hitogata command, and its standard output."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "hitogata", *args], capture_output=True, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise SystemExit(f"hitogata {' '.join(args)} failed: {done.stderr.strip()[-500:]}")
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), done.stdout


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--skip-validate", action="store_true")
    parser.add_argument("--skip-identify", action="store_true")
    options = parser.parse_args()
    figures: dict[str, dict] = {}
    with tempfile.TemporaryDirectory() as tmp:
        wall, cpu, _ = run(["body", "--out", f"{tmp}/body.glb"])
        figures["baseline: hitogata body"] = {"wall_s": wall, "cpu_s": cpu}
        print(f"baseline (hitogata body): {wall:.1f} s wall, {cpu:.1f} s CPU")
        if not options.skip_validate:
            # as docs/validation.md is made: the elastic surface with the literature's and the identified constants
            wall, cpu, out = run(["validate", "--also-materials", "calibrated", "--quiet", "--out",
                                  f"{tmp}/validation"])
            headline = next((line for line in out.splitlines() if line.startswith("within 2 SD")), "")
            figures["hitogata validate"] = {"wall_s": wall, "cpu_s": cpu, "goal_s": 1200.0, "headline": headline}
            print(f"validate: {wall:.0f} s wall ({wall / 1200:.2f} of the 20-minute goal), {cpu:.0f} s CPU; "
                  f"{wall / figures['baseline: hitogata body']['wall_s']:.0f}x the baseline. {headline}")
        if not options.skip_identify:
            wall, cpu, out = run(["identify", "--quiet", "--out", f"{tmp}/materials.toml"])
            fit = next((line for line in out.splitlines() if line.startswith("rows: error")), "")
            figures["hitogata identify"] = {"wall_s": wall, "cpu_s": cpu, "goal_s": 600.0, "fit": fit}
            print(f"identify: {wall:.0f} s wall ({wall / 600:.2f} of the 10-minute goal), {cpu:.0f} s CPU. {fit}")
    RESULTS.parent.mkdir(exist_ok=True)
    RESULTS.write_text(json.dumps(figures, indent=1) + "\n")
    print(f"wrote {RESULTS}")


if __name__ == "__main__":
    main()
