"""Start-up benchmark: `import hitogata`, `hitogata --help` and each package's import, in fresh interpreters.

Goals (issue 13): `import hitogata` ≤ 0.5 s and `hitogata --help` ≤ 0.5 s on this
machine. Baseline, measured in the same run: `python -c "import numpy, scipy.sparse"`,
the least any numerical Python program pays; each figure is printed with its ratio
to it. Each command runs REPEAT times; the median is reported (the machine is shared,
so single runs wander).
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPEAT = 7
SRC = Path(__file__).resolve().parents[1] / "src"
PACKAGES = ["body", "pose", "volume", "fem", "elastic", "dynamics", "motion.scenario", "measure", "report", "render",
            "export"]


def wall(args: list[str]) -> float:
    """Median wall time (s) of running a command to completion."""
    env = {**os.environ, "PYTHONPATH": f"{SRC}{os.pathsep}{os.environ.get('PYTHONPATH', '')}"}
    times = []
    for _ in range(REPEAT):
        start = time.perf_counter()
        subprocess.run(args, check=True, capture_output=True, env=env)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def python(statement: str) -> list[str]:
    return [sys.executable, "-c", statement]


def main() -> None:
    baseline = wall(python("import numpy, scipy.sparse"))
    print(f"baseline `import numpy, scipy.sparse`: {baseline:.3f} s (median of {REPEAT})")
    rows = [
        ("import hitogata", wall(python("import hitogata")), 0.5),
        ("hitogata --help", wall(python("from hitogata.cli import main; main(['--help'])")), 0.5),
    ]
    rows += [(f"import hitogata.{p}", wall(python(f"import hitogata.{p}")), None) for p in PACKAGES]
    for label, seconds, goal in rows:
        target = f" (goal ≤ {goal} s: {'met' if seconds <= goal else 'NOT met'})" if goal else ""
        print(f"{label:<28} {seconds:6.3f} s  {seconds / baseline:5.2f}× baseline{target}")


if __name__ == "__main__":
    main()
