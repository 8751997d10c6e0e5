"""Studies on a real dask.distributed LocalCluster of 2 processes against the same tasks in a plain loop.

Kept cheap: posing by skinning, 3 frames per motion (plus keyframes), 7 bodies (6 across the
supported range, both sexes, BMI 18–34, and one that cannot be built) × 2 motions. Every wait
is on the cluster's state, never a fixed sleep.
"""

import json
import os
import signal
from pathlib import Path

import dask
import numpy as np
import pyarrow.parquet as pq
import pytest

from hitogata.measure.measurements import MEASUREMENT_NAMES
from hitogata.measure.zones import ZONE_NAMES
from hitogata.study.results import percentile_table, read_failures, read_rows, write_tables
from hitogata.study.runner import FAILED, ROWS, run_on_client, run_serial
from hitogata.study.spec import load_study
from waiting import wait_for

STUDIES = Path(__file__).parents[2] / "src" / "hitogata" / "data" / "studies"
CHART = """size,sex,stature_cm,mass_kg
XS,female,150,41
M,female,165,62
XL,female,175,100
S,male,160,50
M,male,178,78
XXL,male,195,130
XL,female,150,160
"""
TASKS, FAILED_TASKS = 14, 2  # 7 bodies x 2 motions; the 150 cm, 160 kg body cannot be built


@pytest.fixture(scope="module")
def study_file(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("study")
    (folder / "chart.csv").write_text(CHART, encoding="utf-8")
    path = folder / "study.toml"
    path.write_text(
        f'motions = ["{STUDIES / "arms_raised.toml"}", "{STUDIES / "sit.toml"}"]\n'
        '[bodies]\nchart = "chart.csv"\n[model]\nframes = 3\n', encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def serial(study_file, tmp_path_factory) -> Path:
    """The reference: every task one by one in a plain loop in this process."""
    out = tmp_path_factory.mktemp("serial")
    summary = run_serial(load_study(study_file), out)
    assert (summary.done, summary.failed, summary.skipped) == (TASKS - FAILED_TASKS, FAILED_TASKS, 0)
    return out


def task_files(out: Path) -> dict[str, Path]:
    return {p.stem: p for p in (out / ROWS).glob("motion=*/*.parquet")}


def assert_same_rows(out: Path, reference: Path) -> None:
    ours, theirs = task_files(out), task_files(reference)
    assert sorted(ours) == sorted(theirs) and len(ours) == TASKS - FAILED_TASKS
    for key, path in theirs.items():
        a, b = pq.read_table(ours[key]), pq.read_table(path)
        assert a.schema == b.schema and a.num_rows == b.num_rows == len(MEASUREMENT_NAMES) + len(ZONE_NAMES)
        for name in a.column_names:  # identical values; NaN where the reference has NaN
            np.testing.assert_array_equal(np.asarray(a.column(name).to_pylist(), dtype=object if
                                                     a.schema.field(name).type == "string" else float),
                                          np.asarray(b.column(name).to_pylist(), dtype=object if
                                                     b.schema.field(name).type == "string" else float))
    assert sorted(p.name for p in (out / FAILED).iterdir()) == sorted(p.name for p in (reference / FAILED).iterdir())


def test_cluster_gives_the_plain_loops_rows_and_records_the_body_that_cannot_be_built(study_file, serial, client,
                                                                                     tmp_path):
    seen = []
    summary = run_on_client(load_study(study_file), tmp_path, client, progress=lambda s: seen.append(s.done + s.failed))
    assert (summary.done, summary.failed) == (TASKS - FAILED_TASKS, FAILED_TASKS)
    assert seen == list(range(1, TASKS + 1))
    assert_same_rows(tmp_path, serial)
    failures = read_failures(tmp_path)
    assert [(f["body"], f["motion"]) for f in failures] == [("XL-8", "arms_raised"), ("XL-8", "sit")]
    assert all(f["error"] == "HitogataError: mass 160.0 kg at stature 150.0 cm: BMI 71.1, allowed up to 50 "
               "(112.5 kg) for adults" for f in failures)
    # What the rows say, for every body: sitting stretches the seat and the knees, raising the arms the shoulders.
    rows = read_rows(tmp_path)
    zone = rows["kind"] == "zone"
    for motion, name in (("sit", "seat"), ("sit", "knee_right"), ("arms_raised", "shoulder_right")):
        stretch = rows["stretch_p95_pct"][zone & (rows["motion"] == motion) & (rows["name"] == name)]
        assert len(stretch) == 6 and np.all(stretch > 30.0), (motion, name, stretch)
    bands, written = write_tables(tmp_path)
    assert {b.group for b in bands} == {"all", "XS", "M", "XL", "S", "XXL"}
    assert written["failed"].read_text(encoding="utf-8").count("XL-8") == 2
    assert percentile_table(read_rows(serial)) == bands


def test_killing_a_worker_mid_study_still_completes(study_file, serial, client, tmp_path):
    before = client.run(os.getpid)
    killed = []

    def kill_one(summary) -> None:
        if not killed:
            address, pid = sorted(before.items())[0]
            os.kill(pid, signal.SIGKILL)
            killed.append(address)

    summary = run_on_client(load_study(study_file), tmp_path, client, progress=kill_one)
    assert killed and summary.done + summary.failed == TASKS
    assert_same_rows(tmp_path, serial)
    # The nanny has started a new worker process in place of the killed one.
    assert wait_for(lambda: len(client.scheduler_info()["workers"]) == 2, timeout=600)
    client.wait_for_workers(2)
    assert set(client.run(os.getpid).values()) != set(before.values())


class Interrupted(Exception):
    pass


def test_rerun_after_an_interruption_computes_only_the_missing_tasks(study_file, serial, client, tmp_path):
    def stop_after_five(summary) -> None:
        if summary.done + summary.failed >= 5:
            raise Interrupted

    spec = load_study(study_file)
    with pytest.raises(Interrupted):
        run_on_client(spec, tmp_path, client, progress=stop_after_five)
    recorded = len(task_files(tmp_path)) + len(list((tmp_path / FAILED).glob("*.json")))
    assert recorded == 5
    again = run_on_client(spec, tmp_path, client)
    assert (again.skipped, again.done + again.failed) == (5, TASKS - 5)
    assert_same_rows(tmp_path, serial)
    # Nothing left: a third run computes nothing.
    assert run_on_client(spec, tmp_path, client).skipped == TASKS
    assert json.loads(next((tmp_path / FAILED).glob("*.json")).read_text())["body"] == "XL-8"


def test_cli_runs_a_study_writes_its_tables_and_a_rerun_computes_nothing(tmp_path, capsys):
    from hitogata.cli import main

    (tmp_path / "chart.csv").write_text("size,sex,stature_cm,mass_kg\nM,male,178,78\n", encoding="utf-8")
    study = tmp_path / "s.toml"
    study.write_text(f'title = "one body"\nmotions = ["{STUDIES / "sit.toml"}"]\n[bodies]\nchart = "chart.csv"\n'
                     '[model]\nframes = 2\n', encoding="utf-8")
    out = tmp_path / "out"
    with dask.config.set({"distributed.comm.timeouts.connect": "300s"}):
        assert main(["study", str(study), "--out", str(out), "--workers", "1", "--memory-limit", "1GiB",
                     "--dashboard", "127.0.0.1:0"]) == 0  # a free port: 8787 may be another's on a shared machine
    printed = capsys.readouterr()
    assert printed.out.startswith("one body: 1 bodies × 1 motions = 1 tasks, 0 done before; size chart chart.csv")
    assert "dask: 1 workers on tcp://" in printed.out and "memory limit per worker 1.0 GiB; dashboard http" in printed.out
    assert "computed 1 tasks, 0 failed" in printed.out
    assert printed.err.startswith("1/1 tasks, 0 failed")  # not a terminal: one line per tenth, no \r
    assert "\r" not in printed.err
    assert sorted(p.name for p in out.iterdir()) == ["bands_sit.png", "failed.csv", "percentiles.csv", "rows"]
    table = (out / "percentiles.csv").read_text(encoding="utf-8").splitlines()
    assert table[0] == "group,motion,kind,name,quantity,unit,n,p5,p50,p95"
    assert any(line.startswith("M,sit,zone,seat,required_stretch,%,1,") for line in table)
    assert main(["study", str(study), "--out", str(out)]) == 0
    again = capsys.readouterr().out
    assert "1 tasks, 1 done before" in again and "dask:" not in again  # no cluster started for nothing
