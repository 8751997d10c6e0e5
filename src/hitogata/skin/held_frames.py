"""Held postures of one body on the free cores: each frame is solved from rest, so the frames are independent.

A pool of worker processes, each with BLAS and the contact's TBB held to one thread
(two cores run two solves, not two solves fighting over four threads), reads the body's whole-body
elastic model from the disk cache (`dynamics.model_cache`: the caller built and
stored it, so a worker starts in a second or two instead of building it again)
and holds the frames it is handed. The answers are the serial ones: the same
model, the same code, each frame on its own. Without the cache (off), with one
core, with fewer than `MIN_FRAMES` frames to hold (a worker takes ~2 s of CPU to
start: imports, the body, the model read), or inside a daemonic process (a Dask
worker may not start processes of its own), the frames are held in this process.
Workers are spawned: a script that starts them needs the `if __name__ == "__main__":`
guard (the commands have it).
"""

from __future__ import annotations

import multiprocessing
import os
import weakref
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool

import numpy as np

from hitogata import disk_cache
from hitogata.body.model import Body
from hitogata.dynamics.motion import BodyDynamics
from hitogata.skin import single_pose
from hitogata.skin.single_pose import elastic_dynamics
from hitogata.skin.settings import SKIN_DEFAULTS, SkinSettings
from hitogata.elastic.materials import Materials, load_materials
from hitogata.geometry.ipc_toolkit import prepare_toolkit

MIN_FRAMES = 10  # fewer frames than this are held here: starting the workers would cost more than they save
_WORKER: dict[str, object] = {}  # a worker process's model and options (`_start`)


def available_cores() -> int:
    """The cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def free_cores() -> int:
    """The cores not busy with other work (the one-minute load less this process), at least 1: a worker
    beyond them only shares a core, and costs its start (a deep squat's 19 frames on a machine whose
    other core was busy: 58 s on two workers against 47 s in this process)."""
    cores = available_cores()
    try:
        load = os.getloadavg()[0]
    except (OSError, AttributeError):  # no load average on this platform
        return cores
    return max(1, min(cores, round(cores - max(load - 1.0, 0.0))))


class HeldFrames:
    """Held skins (V, 3) of joint-angle postures (rest-relative radians, clamped onto the range of motion),
    with the skin's self-contact resolved when `contact` (`elastic_pose`, with the constants of `settings`),
    on `workers` processes (None: the cores free of other work, `free_cores`)."""

    def __init__(self, body: Body, contact: bool = True, workers: int | None = None,
                 materials: Materials | None = None, settings: SkinSettings = SKIN_DEFAULTS) -> None:
        self.body, self.contact, self.materials, self.settings = body, contact, materials, settings
        # built and stored before any worker reads it
        self.dynamics: BodyDynamics = elastic_dynamics(body, materials=materials)
        self.workers = free_cores() if workers is None else max(int(workers), 1)
        self._pool: ProcessPoolExecutor | None = None

    def __call__(self, angles: np.ndarray) -> list[np.ndarray]:
        """The held skin of each posture (F, D)."""
        angles = np.atleast_2d(np.asarray(angles, dtype=float))
        if self._parallel(len(angles)):
            try:
                return list(self._workers().map(_held, list(angles)))
            except BrokenProcessPool as err:  # a worker died (out of memory, killed): hold them here
                disk_cache.note(f"the worker processes stopped ({err}); the frames are held in this process")
                self.workers, self._pool = 1, None
        return [self._hold(q) for q in angles]

    def _parallel(self, frames: int) -> bool:
        return (frames >= MIN_FRAMES and self.workers > 1 and disk_cache.enabled()
                and not multiprocessing.current_process().daemon)

    def _hold(self, q: np.ndarray) -> np.ndarray:
        return single_pose.elastic_pose(self.dynamics, angles=q, contact=self.contact, on_limit="clamp",
                                        settings=self.settings).vertices

    def _workers(self) -> ProcessPoolExecutor:
        if self._pool is None:
            body = self.body
            self._pool = ProcessPoolExecutor(self.workers, multiprocessing.get_context("spawn"), _start,
                                             (body.params, body.all_vertices, body.density, self.contact,
                                              None if self.materials is None else self.materials.source,
                                              self.settings))
            weakref.finalize(self, self._pool.shutdown, wait=False, cancel_futures=True)
        return self._pool

    def close(self) -> None:
        """Stop the worker processes (also done when this is dropped, or at exit)."""
        if self._pool is not None:
            self._pool.shutdown()
            self._pool = None


def _start(params, all_vertices: np.ndarray, density: float, contact: bool, materials: str | None,
           settings: SkinSettings) -> None:
    """A worker's start: BLAS and the contact's TBB on one thread (the workers are the parallelism), the
    body's model read from the disk cache (`materials`: the file the parent's were read from), the parent's
    contact settings."""
    from threadpoolctl import threadpool_limits

    threadpool_limits(1)
    prepare_toolkit()
    _WORKER["dynamics"] = elastic_dynamics(Body(params, all_vertices, density),
                                           materials=None if materials is None else load_materials(materials))
    _WORKER["contact"] = contact
    _WORKER["settings"] = settings


def _held(q: np.ndarray) -> np.ndarray:
    dynamics, settings = _WORKER["dynamics"], _WORKER["settings"]
    assert isinstance(dynamics, BodyDynamics) and isinstance(settings, SkinSettings)
    return single_pose.elastic_pose(dynamics, angles=q, contact=bool(_WORKER["contact"]), on_limit="clamp",
                                    settings=settings).vertices
