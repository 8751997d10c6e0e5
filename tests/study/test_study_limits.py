"""`hitogata study` on this machine only, within its means, and stopped cleanly.

The dashboard, scheduler and workers listen on 127.0.0.1; Ctrl-C sent to the
whole process group (as a terminal does) ends with one line and no worker's
traceback; a memory limit too small for a task, an unreachable scheduler and
more workers than the machine holds are answered before Dask starts.
"""

from __future__ import annotations

import ipaddress
import os
import signal
import socket
import subprocess
import sys
from pathlib import Path

import psutil
import pytest

from hitogata import cli
from hitogata.commands.study import capped_workers, expected_time
from hitogata.machine import cores
from waiting import wait_for

SOURCE = str(Path(cli.__file__).parents[1])


def one_line_error(argv: list[str], capsys) -> str:
    code = cli.main(argv)
    err = capsys.readouterr().err
    assert code == 2 and "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    return err.strip()


def test_a_memory_limit_too_small_for_a_task_is_refused_before_dask(tmp_path, capsys):
    line = one_line_error(["study", "example", "--out", str(tmp_path / "r"), "--memory-limit", "1MiB"], capsys)
    assert line == ("hitogata: error: argument --memory-limit: memory limit 1MiB: allowed at least 512 MiB per "
                    "worker (a task posing by skinning peaks at 0.35 GiB)")
    assert list(tmp_path.iterdir()) == []


def test_a_refused_scheduler_address_fails_at_once(tmp_path, capsys):
    with socket.socket() as free:  # a port nothing listens on
        free.bind(("127.0.0.1", 0))
        port = free.getsockname()[1]
    line = one_line_error(["study", "example", "--out", str(tmp_path / "r"), "--scheduler", f"tcp://127.0.0.1:{port}"],
                          capsys)
    assert line.startswith(f"hitogata: error: --scheduler tcp://127.0.0.1:{port}: cannot reach it (Connection refused")
    assert list(tmp_path.iterdir()) == []


def test_workers_are_capped_by_cores_and_memory(capsys):
    n = capped_workers(1000, "1GiB")
    assert 1 <= n <= cores()
    said = capsys.readouterr().out
    assert said.startswith(f"--workers 1000: capped at {n} (") and "GiB free memory, 1GiB per worker)" in said
    assert capped_workers(1, "1GiB") == 1 and capsys.readouterr().out == ""


def test_the_expected_time_is_said_from_the_measured_rates():
    line = expected_time(400, 2, "skinning")
    assert line.startswith("400 tasks on 2 workers: about 8–37 min")


def listening_addresses(pid: int) -> set[str]:
    processes = [psutil.Process(pid), *psutil.Process(pid).children(recursive=True)]
    found = set()
    for process in processes:
        try:
            found |= {c.laddr.ip for c in process.net_connections(kind="inet") if c.status == psutil.CONN_LISTEN}
        except psutil.NoSuchProcess:
            pass
    return found


def test_the_study_listens_on_this_machine_only_and_ctrl_c_is_one_line(tmp_path):
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([SOURCE, os.environ.get("PYTHONPATH", "")])}
    out = tmp_path / "results"
    proc = subprocess.Popen([sys.executable, "-m", "hitogata.cli", "study", "example", "--out", str(out),
                             "--workers", "1", "--memory-limit", "1GiB", "--dashboard", "127.0.0.1:0"],
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        lines = []
        while not lines or not lines[-1].startswith("dask:"):
            lines.append(proc.stdout.readline())
            assert lines[-1], "the study ended before its cluster started"
        assert lines[1].startswith("400 tasks on 1 workers: about ")  # its size and time, up front
        assert "dashboard http://127.0.0.1:" in lines[-1]
        assert wait_for(lambda: len(listening_addresses(proc.pid)) > 0)
        addresses = listening_addresses(proc.pid)
        assert all(ipaddress.ip_address(a).is_loopback for a in addresses), addresses
        os.killpg(proc.pid, signal.SIGINT)  # what a terminal's Ctrl-C does: the whole group
        _, err = proc.communicate()
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 130, err
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err
    assert "interrupted: " in err and "the same command resumes" in err
    assert not out.exists() or any(out.iterdir())  # no empty folder


@pytest.mark.parametrize("text", ["0.0.0.0", "host:port", ":99999"])
def test_a_wrong_dashboard_address_is_one_line(tmp_path, capsys, text):
    line = one_line_error(["study", "example", "--out", str(tmp_path / "r"), "--dashboard", text], capsys)
    assert line.startswith(f"hitogata: error: argument --dashboard: dashboard '{text}': allowed host:port")
