"""Wall-clock timing shared by the benchmark scripts."""

from __future__ import annotations

import resource
import subprocess
import time
from collections.abc import Mapping
from typing import Callable


def timed(fn: Callable[[], object], repeat: int) -> list[float]:
    """Seconds each of `repeat` calls of fn took."""
    out = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        out.append(time.perf_counter() - start)
    return out


def timed_process(argv: list[str], env: Mapping[str, str], **run) -> tuple[float, float]:
    """Wall and CPU seconds (user + system, the child's own) of one command run to its end (check=True)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run(argv, env=dict(env), check=True, **run)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
