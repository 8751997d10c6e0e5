"""What this machine can give a run: its cores and free memory, checked before a large allocation or many workers."""

from __future__ import annotations

import os

import psutil

from hitogata.errors import HitogataError


def cores() -> int:
    """The cores this process may run on (its affinity, not the whole machine's)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


def available_memory() -> int:
    """Bytes of memory free for a new allocation (free plus reclaimable cache)."""
    return int(psutil.virtual_memory().available)


def require_memory(needed: float, what: str) -> None:
    """One line, before allocating, if `needed` bytes exceed the memory free now."""
    free = available_memory()
    if needed > free:
        raise HitogataError(f"{what}: needs {needed / 2**30:.3g} GiB of memory, {free / 2**30:.1f} GiB free; "
                            "allowed a smaller run")
