"""Run a study's tasks on dask.distributed: a local cluster of processes, or an existing scheduler.

Every (body, motion) task is submitted to the cluster; as each finishes, its
rows are written here, atomically, as one Parquet file named by the task's
hash in a dataset partitioned by motion (`rows/motion=<name>/<hash>.parquet`),
or its one-line error as `failed/<hash>.json`. A rerun submits only the tasks
with neither file, so an interrupted study resumes where it stopped. A worker
process that dies is Dask's business: its nanny starts a new one and the
scheduler runs the lost tasks again (up to `distributed.scheduler.allowed-
failures` deaths per task, after which the task is recorded as failed). The
body-independent data is loaded once per worker by a worker plugin.
"""

from __future__ import annotations

import json
import logging
import os
import secrets
import signal
import threading
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq
from distributed import WorkerPlugin

from hitogata.errors import HitogataError, warnings_as_lines
from hitogata.export.atomic import write_bytes_atomically
from hitogata.study.spec import StudySpec
from hitogata.study.tasks import COLUMNS, Outcome, Task, execute, warm

MEMORY_LIMIT = "2GiB"  # per worker: posing by skinning peaks at 0.35 GiB (docs/study.md); the elastic body needs more
ROWS, FAILED = "rows", "failed"
# The files hold every column but the motion, which the dataset's partitioning (motion=<name>) gives.
SCHEMA = pa.schema([(name, pa.string() if kind == "str" else pa.float64()) for name, kind in COLUMNS.items()
                    if name != "motion"])


def plan(spec: StudySpec) -> list[Task]:
    """Every (body, motion) task of the study, bodies outermost."""
    return [Task(body, motion, spec.model, spec.outputs) for body in spec.bodies for motion in spec.motions]


def rows_path(out: Path, task: Task) -> Path:
    return out / ROWS / f"motion={task.motion.name}" / f"{task.key}.parquet"


def failed_path(out: Path, task: Task) -> Path:
    return out / FAILED / f"{task.key}.json"


def pending(tasks: Iterable[Task], out: Path, retry_failed: bool = False) -> list[Task]:
    """The tasks with no rows yet (nor a recorded failure, unless those are to be tried again)."""
    return [t for t in tasks if not rows_path(out, t).exists() and (retry_failed or not failed_path(out, t).exists())]


def rows_table(rows: dict[str, list]) -> pa.Table:
    return pa.table({name: pa.array(rows[name], type=SCHEMA.field(name).type) for name in SCHEMA.names},
                    schema=SCHEMA)


def record(out: Path, task: Task, outcome: Outcome) -> None:
    """Write a task's rows (Parquet) or its error (JSON), atomically; a retried failure's old record goes."""
    if outcome.error is None:
        if outcome.rows is None:  # execute gives rows or an error, never neither
            raise HitogataError(f"task {task.key}: no rows and no error")
        path = rows_path(out, task)
        path.parent.mkdir(parents=True, exist_ok=True)
        sink = pa.BufferOutputStream()
        pq.write_table(rows_table(outcome.rows), sink)
        write_bytes_atomically(path, sink.getvalue().to_pybytes())
        failed_path(out, task).unlink(missing_ok=True)
        return
    path = failed_path(out, task)
    path.parent.mkdir(parents=True, exist_ok=True)
    entry = {"task": task.key, "body": task.body.id, "group": task.body.group, "motion": task.motion.name,
             "error": outcome.error}
    write_bytes_atomically(path, (json.dumps(entry) + "\n").encode())


@dataclass
class RunSummary:
    """What a run did: tasks in the study, already done before, computed now, failed now; times (s)."""

    total: int
    skipped: int
    done: int = 0
    failed: int = 0
    wall_seconds: float = 0.0
    task_seconds: float = 0.0  # summed wall time inside the tasks
    task_cpu_seconds: float = 0.0  # summed CPU time inside the tasks (below the wall time on a busy machine)

    @property
    def rate_per_minute(self) -> float:
        return 60.0 * (self.done + self.failed) / self.wall_seconds if self.wall_seconds > 0 else 0.0


Progress = Callable[[RunSummary], None]


def run_serial(spec: StudySpec, out: str | os.PathLike, progress: Progress | None = None,
               retry_failed: bool = False) -> RunSummary:
    """The same study in a plain loop in this process: the baseline and the reference answer."""
    out = _out_dir(out)
    tasks = plan(spec)
    todo = pending(tasks, out, retry_failed)
    summary = RunSummary(len(tasks), len(tasks) - len(todo))
    start = time.perf_counter()
    for task in todo:
        _count(summary, out, task, execute(task), start, progress)
    return summary


def run_on_client(spec: StudySpec, out: str | os.PathLike, client, progress: Progress | None = None,
                  retry_failed: bool = False) -> RunSummary:
    """Run the study's missing tasks on a dask.distributed client's workers; rows written as they come."""
    from distributed import as_completed

    out = _out_dir(out)
    tasks = plan(spec)
    todo = pending(tasks, out, retry_failed)
    summary = RunSummary(len(tasks), len(tasks) - len(todo))
    if not todo:
        return summary
    client.register_plugin(WarmWorker(), name="hitogata-study-warm")
    run = secrets.token_hex(3)  # keys unique to this run: a cancelled earlier run's keys may linger
    by_key = {f"study-{t.key}-{run}": t for t in todo}
    start = time.perf_counter()
    futures = client.map(execute, todo, key=list(by_key), pure=False)
    try:
        for future in as_completed(futures):
            task = by_key[future.key]
            try:
                outcome = future.result()
            except Exception as error:  # the engine gave up on it (KilledWorker: it killed 3 workers), or cancelled
                outcome = Outcome(task.key, None, f"{type(error).__name__}: {' '.join(str(error).split())}", 0.0)
            future.release()
            _count(summary, out, task, outcome, start, progress)
    finally:
        client.cancel([f for f in futures if not f.done()])
    return summary


def _count(summary: RunSummary, out: Path, task: Task, outcome: Outcome, start: float,
           progress: Progress | None) -> None:
    record(out, task, outcome)
    summary.task_seconds += outcome.seconds
    summary.task_cpu_seconds += outcome.cpu_seconds
    if outcome.error is None:
        summary.done += 1
    else:
        summary.failed += 1
    summary.wall_seconds = time.perf_counter() - start
    if progress is not None:
        progress(summary)


def _out_dir(out: str | os.PathLike) -> Path:
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise HitogataError(f"{out}: not a folder; allowed a folder for the study's results")
    out.mkdir(parents=True, exist_ok=True)
    return out


class WarmWorker(WorkerPlugin):
    """Worker plugin: load the body-independent data once when a worker starts (and when it restarts); warnings
    as one line each, once."""

    idempotent = True

    def setup(self, worker) -> None:
        warnings_as_lines()  # a warning raised for every body is said once per worker, as one line
        warm()


def local_cluster(workers: int, memory_limit: str = MEMORY_LIMIT, dashboard: str | None = "127.0.0.1:8787"):
    """A LocalCluster of `workers` single-threaded processes, started and waited for (not a fixed sleep).

    Everything listens on this machine only: the scheduler and workers on 127.0.0.1, the dashboard
    where `dashboard` says (host:port; None: no dashboard). The worker processes start with Ctrl-C
    ignored: the terminal sends it to the whole process group, and the command, not each worker,
    answers it (the cluster is closed, no worker prints a traceback). Dask's own log lines are kept to
    the critical ones: a task's failure reaches the command through its future and is said there, and a
    worker whose heartbeat meets the scheduler closing on Ctrl-C logs a traceback at ERROR level.
    """
    from distributed import Client, LocalCluster

    main = threading.current_thread() is threading.main_thread()  # signals are set in the main thread only
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
    try:
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, memory_limit=memory_limit,
                               host="127.0.0.1", dashboard_address=dashboard, silence_logs=logging.CRITICAL)
    finally:
        if main:
            signal.signal(signal.SIGINT, previous)
    client = Client(cluster)
    client.wait_for_workers(workers)
    return cluster, client

