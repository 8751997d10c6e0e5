"""Wall-clock timing shared by the benchmark scripts."""

from __future__ import annotations

import time
from typing import Callable


def timed(fn: Callable[[], object], repeat: int) -> list[float]:
    """Seconds each of `repeat` calls of fn took."""
    out = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        out.append(time.perf_counter() - start)
    return out
