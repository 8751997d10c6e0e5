"""A background job that lags behind the sliders: run on request, coalescing requests made meanwhile.

Measurements (~50 ms) and strain colours (~10 ms) are too slow for every
slider event; each runs on its own thread, always on the latest frame, so a
drag costs one run per finished run rather than one per event. A run may
wait `delay` seconds after the request first: Python threads share one
interpreter lock, and the wait lets the frame's own update go out to the
browser before the heavy run begins.
"""

from __future__ import annotations

import sys
import threading
import time
import traceback
from collections.abc import Callable


class Worker:
    """Runs `job()` on its own daemon thread whenever `request()` was called since its last start."""

    def __init__(
        self, job: Callable[[], None], name: str, on_error: Callable[[str], None], delay: float = 0.0
    ) -> None:
        self._job, self._on_error, self._delay = job, on_error, delay
        self._wanted = threading.Event()
        self._stopping = False
        self._idle = threading.Event()
        self._idle.set()
        self._lock = threading.Lock()  # keeps `idle` from being set over a request just made
        self._thread = threading.Thread(target=self._loop, name=name, daemon=True)
        self._thread.start()

    def request(self) -> None:
        with self._lock:
            self._idle.clear()
            self._wanted.set()

    def wait_idle(self, timeout: float | None = None) -> bool:
        """Block until no run is pending (for tests and benchmarks); False on timeout."""
        return self._idle.wait(timeout)

    def stop(self) -> None:
        self._stopping = True
        self._wanted.set()
        self._thread.join(timeout=5.0)

    def _loop(self) -> None:
        while True:
            self._wanted.wait()
            if self._stopping:
                return
            time.sleep(self._delay)
            self._wanted.clear()
            try:
                self._job()
            except Exception as exc:  # a failed run must not end the thread: report and go on
                traceback.print_exc(file=sys.stderr)
                self._on_error(f"{self._thread.name}: {exc}")
            with self._lock:
                if not self._wanted.is_set():
                    self._idle.set()
