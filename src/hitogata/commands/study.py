"""`hitogata study`: run a population study (bodies × motions) on dask.distributed, then its tables and plots."""

from __future__ import annotations

import argparse
import os
import sys
from importlib import resources
from pathlib import Path

from hitogata.errors import HitogataError, excerpt

SCHEDULER_TIMEOUT = "30s"
PROBE_SECONDS = 5.0  # a scheduler's port that neither answers nor refuses within this is left to Dask's timeout
MIN_MEMORY = 512 * 2**20  # bytes per worker
# tasks a minute a worker, posing by skinning (docs/study.md, "Measured here"): 2 workers on a 2-core
# machine shared with other jobs (10.7 tasks/min) and on the quiet machine (51.6 tasks/min)
TASKS_PER_MINUTE_PER_WORKER = (5.35, 25.8)


def shipped_studies() -> dict[str, Path]:
    """The example studies shipped with the package, by name."""
    folder = resources.files("hitogata") / "data" / "studies"
    return {p.name.removesuffix(".toml"): Path(str(p)) for p in folder.iterdir()
            if p.name.endswith(".toml") and "[bodies]" in p.read_text(encoding="utf-8")}


def memory(text: str) -> str:
    """A memory size per worker as Dask reads it ('2GiB', '1500MB'), at least what one task needs."""
    from dask.utils import parse_bytes

    try:
        size = parse_bytes(text)
    except (ValueError, TypeError):
        size = -1
    if size <= 0:
        raise argparse.ArgumentTypeError(f"memory limit {text!r}: allowed a size like 2GiB or 1500MB")
    if size < MIN_MEMORY:
        raise argparse.ArgumentTypeError(f"memory limit {text}: allowed at least {MIN_MEMORY / 2**20:.0f} MiB per "
                                         "worker (a task posing by skinning peaks at 0.35 GiB)")
    return text


def workers(text: str) -> int:
    try:
        n = int(text)
        if n < 1:
            raise ValueError
    except ValueError:
        raise argparse.ArgumentTypeError(f"workers {text!r}: allowed a whole number >= 1") from None
    return n


def dashboard(text: str) -> str | None:
    """Where the Dask dashboard listens: host:port, or none."""
    if text.lower() == "none":
        return None
    host, colon, port = text.rpartition(":")
    if not colon or not host or not port.isdigit() or not 0 <= int(port) <= 65535:
        raise argparse.ArgumentTypeError(f"dashboard {text!r}: allowed host:port (e.g. 127.0.0.1:8787) or none")
    return text


def capped_workers(asked: int, memory_limit: str) -> int:
    """`asked`, or fewer: at most one worker per core and per `memory_limit` of free memory (said in a line)."""
    from dask.utils import parse_bytes

    from hitogata.machine import available_memory, cores

    n_cores, free = cores(), available_memory()
    cap = max(1, min(n_cores, free // parse_bytes(memory_limit)))
    if asked > cap:
        print(f"--workers {asked}: capped at {cap} ({n_cores} cores; {free / 2**30:.1f} GiB free memory, "
              f"{memory_limit} per worker)", flush=True)
    return min(asked, cap)


def expected_time(tasks: int, n_workers: int, posing: str) -> str:
    """A line saying how long `tasks` take on `n_workers` local workers, from the rates measured (docs/study.md)."""
    if posing != "skinning":
        return f"{tasks} tasks posed by the elastic body: minutes a body on each of {n_workers} workers"
    slow, fast = (tasks / (n_workers * rate) for rate in TASKS_PER_MINUTE_PER_WORKER)
    return (f"{tasks} tasks on {n_workers} workers: about {fast:.0f}–{slow:.0f} min "
            f"({TASKS_PER_MINUTE_PER_WORKER[0]:g}–{TASKS_PER_MINUTE_PER_WORKER[1]:g} tasks/min a worker measured "
            "on a busy and a quiet 2-core machine, docs/study.md); Ctrl-C stops, the same command resumes")


def reachable(address: str) -> None:
    """Fail at once when nothing listens at a tcp:// scheduler address (Dask would retry until its timeout)."""
    import socket
    from urllib.parse import urlsplit

    if not address.startswith("tcp://"):
        return
    try:
        parts = urlsplit(address)
        host, port = parts.hostname, parts.port
    except ValueError:
        host, port = None, None
    if not host or port is None:
        raise HitogataError(f"--scheduler {excerpt(address)}: allowed an address like tcp://host:8786")
    try:
        socket.create_connection((host, port), timeout=PROBE_SECONDS).close()
    except (ConnectionRefusedError, socket.gaierror) as err:
        raise HitogataError(f"--scheduler {address}: cannot reach it ({err.strerror or err})") from None
    except OSError:  # no answer within the probe's time: let Dask try for its own timeout
        pass


def connect(args: argparse.Namespace):
    """(cluster or None, client): a new LocalCluster, or the scheduler given."""
    from distributed import Client

    from hitogata.study.runner import local_cluster

    if args.scheduler is None:
        return local_cluster(args.workers, args.memory_limit, args.dashboard)
    if not args.scheduler.startswith(("tcp://", "tls://", "ucx://", "inproc://")):
        raise HitogataError(f"--scheduler {excerpt(args.scheduler)}: allowed an address like tcp://host:8786")
    reachable(args.scheduler)
    try:
        return None, Client(args.scheduler, timeout=SCHEDULER_TIMEOUT)
    except (OSError, TimeoutError) as err:
        raise HitogataError(f"--scheduler {args.scheduler}: cannot reach it ({' '.join(str(err).split())})") from None


def run(args: argparse.Namespace) -> None:
    from hitogata.study.plots import write_plots
    from hitogata.study.progress import ProgressLine
    from hitogata.study.results import write_tables
    from hitogata.study.runner import pending, plan, run_on_client
    from hitogata.study.spec import load_study

    shipped = shipped_studies()
    spec = load_study(shipped[args.study] if args.study in shipped else args.study)
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise HitogataError(f"--out {out}: not a folder; allowed a folder for the results")
    tasks = plan(spec)
    todo = pending(tasks, out, args.retry_failed) if out.is_dir() else tasks
    print(f"{spec.title}: {len(spec.bodies)} bodies × {len(spec.motions)} motions = {len(tasks)} tasks, "
          f"{len(tasks) - len(todo)} done before; {spec.population}", flush=True)
    if todo:
        if args.scheduler is None:
            args.workers = capped_workers(args.workers, args.memory_limit)
            print(expected_time(len(todo), args.workers, spec.model.posing), flush=True)
        created = not out.exists()
        cluster, client = connect(args)
        try:
            info = client.scheduler_info()["workers"]
            limit = {w.get("memory_limit", 0) for w in info.values()}
            print(f"dask: {len(info)} workers on {client.scheduler.address}, memory limit per worker "
                  f"{', '.join(f'{m / 2**30:.1f} GiB' for m in sorted(limit))}; dashboard {client.dashboard_link}")
            progress = None if args.quiet else ProgressLine(sys.stderr)
            summary = run_on_client(spec, out, client, progress, args.retry_failed)
        except KeyboardInterrupt:
            done = len(tasks) - len(pending(tasks, out, args.retry_failed))
            print(f"\ninterrupted: {done} of {len(tasks)} tasks recorded in {out}/; the same command resumes",
                  file=sys.stderr)
            raise SystemExit(130) from None
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
            if created and out.is_dir() and not any(out.iterdir()):
                out.rmdir()  # nothing recorded: no empty folder left
        print(f"computed {summary.done} tasks, {summary.failed} failed, in {summary.wall_seconds:.0f} s "
              f"({summary.rate_per_minute:.1f} tasks/min)")
    bands, written = write_tables(out)
    plots = write_plots(bands, out, spec.title)
    print(f"wrote {', '.join(p.name for p in written.values())} and {len(plots)} plots in {out}/ "
          f"(rows: {out}/rows/, Parquet partitioned by motion)")


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("study", help="a population study on dask.distributed: bodies × motions → ease, stretch")
    parser.add_argument("study", help="a study file (docs/study.md) or a shipped one: example (adults), children (six-year-olds)")
    parser.add_argument("--out", default="results", help="results folder; a rerun computes only missing tasks")
    parser.add_argument("--workers", type=workers, default=os.cpu_count() or 1,
                        help="local worker processes (one thread each); default: the CPU count; capped by the "
                             "cores and the free memory (--memory-limit each)")
    parser.add_argument("--memory-limit", type=memory, default="2GiB",
                        help="per local worker, at least 512MiB; default 2GiB")
    parser.add_argument("--dashboard", type=dashboard, default="127.0.0.1:8787",
                        help="where Dask's dashboard listens: host:port or none; default 127.0.0.1:8787 "
                             "(this machine only; 0.0.0.0:8787 opens it to the network)")
    parser.add_argument("--scheduler", default=None,
                        help="an existing Dask scheduler, e.g. tcp://host:8786 (then --workers is not used)")
    parser.add_argument("--retry-failed", action="store_true", help="run the tasks that failed before again")
    parser.add_argument("--quiet", action="store_true", help="no progress line")
    parser.set_defaults(run=run)
