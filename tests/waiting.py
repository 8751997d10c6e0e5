"""Polling for tests that watch a server or a browser change state.

Tests wait on state, never on the clock: `PATIENCE` is only the bound after
which a state that never comes counts as a failure, so it is generous (a busy
shared machine can be 10x slower than an idle one) and costs nothing when the
state arrives.
"""

import time

PATIENCE = 600.0  # seconds


def wait_for(predicate, timeout: float = PATIENCE) -> bool:
    """True as soon as `predicate()` is, False if it is not within `timeout` seconds (polled every 50 ms)."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return True
        time.sleep(0.05)
    return False
