"""Polling for tests that watch a server or a browser change state."""

import time


def wait_for(predicate, timeout: float = 30.0) -> bool:
    """True as soon as `predicate()` is, False if it is not within `timeout` seconds (polled every 50 ms)."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return True
        time.sleep(0.05)
    return False
