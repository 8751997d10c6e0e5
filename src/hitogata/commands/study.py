"""`hitogata study`: run a population study (bodies × motions) on dask.distributed, then its tables and plots."""

from __future__ import annotations

import argparse
import os
import sys
from importlib import resources
from pathlib import Path

from hitogata.errors import HitogataError

SCHEDULER_TIMEOUT = "30s"


def shipped_studies() -> dict[str, Path]:
    """The example studies shipped with the package, by name."""
    folder = resources.files("hitogata") / "data" / "studies"
    return {p.name.removesuffix(".toml"): Path(str(p)) for p in folder.iterdir()
            if p.name.endswith(".toml") and "[bodies]" in p.read_text(encoding="utf-8")}


def memory(text: str) -> str:
    """A memory size as Dask reads it ('2GiB', '1500MB')."""
    from dask.utils import parse_bytes

    try:
        if parse_bytes(text) <= 0:
            raise ValueError
    except (ValueError, TypeError):
        raise argparse.ArgumentTypeError(f"memory limit {text!r}: allowed a size like 2GiB or 1500MB") from None
    return text


def workers(text: str) -> int:
    try:
        n = int(text)
        if n < 1:
            raise ValueError
    except ValueError:
        raise argparse.ArgumentTypeError(f"workers {text!r}: allowed a whole number >= 1") from None
    return n


def connect(args: argparse.Namespace):
    """(cluster or None, client): a new LocalCluster, or the scheduler given."""
    from distributed import Client

    from hitogata.study.runner import local_cluster

    if args.scheduler is None:
        return local_cluster(args.workers, args.memory_limit)
    if not args.scheduler.startswith(("tcp://", "tls://", "ucx://", "inproc://")):
        raise HitogataError(f"--scheduler {args.scheduler!r}: allowed an address like tcp://host:8786")
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
          f"{len(tasks) - len(todo)} done before; {spec.population}")
    if todo:
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
        print(f"computed {summary.done} tasks, {summary.failed} failed, in {summary.wall_seconds:.0f} s "
              f"({summary.rate_per_minute:.1f} tasks/min)")
    bands, written = write_tables(out)
    plots = write_plots(bands, out, spec.title)
    print(f"wrote {', '.join(p.name for p in written.values())} and {len(plots)} plots in {out}/ "
          f"(rows: {out}/rows/, Parquet partitioned by motion)")


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("study", help="a population study on dask.distributed: bodies × motions → ease, stretch")
    parser.add_argument("study", help="a study file (docs/study.md) or a shipped one: example")
    parser.add_argument("--out", default="results", help="results folder; a rerun computes only missing tasks")
    parser.add_argument("--workers", type=workers, default=os.cpu_count() or 1,
                        help="local worker processes (one thread each); default: the CPU count")
    parser.add_argument("--memory-limit", type=memory, default="2GiB", help="per local worker; default 2GiB")
    parser.add_argument("--scheduler", default=None,
                        help="an existing Dask scheduler, e.g. tcp://host:8786 (then --workers is not used)")
    parser.add_argument("--retry-failed", action="store_true", help="run the tasks that failed before again")
    parser.add_argument("--quiet", action="store_true", help="no progress line")
    parser.set_defaults(run=run)
