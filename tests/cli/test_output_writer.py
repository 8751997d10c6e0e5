"""The one output writer: a lock per target, no merge into a folder filled meanwhile, no symlink replaced
unasked, SIGTERM taken like Ctrl-C, stale staging removed, a full disk one line, related files as one unit.

Signals and a full disk are real: the command runs in a child process, sent
SIGINT or SIGTERM while its staging folder exists, or started with a file-size
limit (RLIMIT_FSIZE: a write past it fails as on a full disk). Every wait is on
the state of the folder, never on the clock.
"""

from __future__ import annotations

import os
import resource
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from hitogata import cli
from hitogata.commands.paths import output_lock, staged_folder
from hitogata.errors import HitogataError
from hitogata.export.atomic import write_files_together
from waiting import wait_for

SOURCE = str(Path(cli.__file__).parents[1])
LONG_SCENARIO = """[model]
element_size = "60mm"
modes = 4
[time]
duration = "60s"
rate = 30
[output]
files = ["glb"]
[[keyframe]]
time = "0.5s"
clinical = { "forearm_l.flexion" = "60deg" }
"""


def files_in(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


def start(argv: list[str], folder: Path, limit_bytes: int | None = None) -> subprocess.Popen:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([SOURCE, os.environ.get("PYTHONPATH", "")])}

    def limited() -> None:
        if limit_bytes is not None:
            resource.setrlimit(resource.RLIMIT_FSIZE, (limit_bytes, limit_bytes))

    return subprocess.Popen([sys.executable, "-m", "hitogata.cli", *argv], cwd=folder, env=env, text=True,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, preexec_fn=limited)


def staging_exists(folder: Path, proc: subprocess.Popen) -> bool:
    return any(p.name.startswith(".results.partial") for p in folder.iterdir()) or proc.poll() is not None


@pytest.mark.parametrize("signum, code, word", [(signal.SIGTERM, 143, "terminated"), (signal.SIGINT, 130, "interrupted")])
def test_a_second_writer_is_refused_and_a_signal_leaves_nothing(tmp_path, capsys, monkeypatch, signum, code, word):
    (tmp_path / "s.toml").write_text(LONG_SCENARIO)
    first = start(["simulate", "s.toml", "--out", "results"], tmp_path)
    try:
        assert wait_for(lambda: staging_exists(tmp_path, first))
        assert first.poll() is None, first.stderr.read() if first.stderr else ""
        monkeypatch.chdir(tmp_path)
        assert cli.main(["simulate", "s.toml", "--out", "results"]) == 2  # the same target, meanwhile
        assert capsys.readouterr().err == ("hitogata: error: --out results: another hitogata command is writing it "
                                           "now; wait for it to finish or choose another --out\n")
        first.send_signal(signum)  # what `timeout`, systemd and CI send; Ctrl-C
        _, err = first.communicate()
    finally:
        first.kill()
    assert first.returncode == code, err
    assert err.strip() == f"hitogata: {word}; nothing written"
    assert files_in(tmp_path) == ["s.toml"]


def test_a_folder_filled_meanwhile_is_not_merged_into(tmp_path):
    target = tmp_path / "out"
    with pytest.raises(HitogataError, match="the folder was filled by another program while this command ran"):
        with staged_folder(target, force=False) as staging:
            (staging / "ours.txt").write_text("ours")
            target.mkdir()
            (target / "theirs.txt").write_text("theirs")
    assert files_in(tmp_path) == ["out", "out/theirs.txt"]


def test_stale_staging_and_temporary_files_of_the_target_are_removed_by_the_next_writer(tmp_path):
    (tmp_path / ".results.partial-0badf00d").mkdir()
    (tmp_path / ".results.partial-0badf00d" / "half.glb").write_bytes(b"half")
    (tmp_path / ".b.glb.0badf00d.tmp-hitogata").write_bytes(b"half")
    (tmp_path / ".other.partial-12345678").mkdir()  # another target's: not ours to remove
    with output_lock(tmp_path / "results"):
        assert not (tmp_path / ".results.partial-0badf00d").exists()
    with output_lock(tmp_path / "b.glb"):
        assert not (tmp_path / ".b.glb.0badf00d.tmp-hitogata").exists()
    assert files_in(tmp_path) == [".other.partial-12345678"]


@pytest.mark.parametrize("link, state", [("nowhere", "dangling, to nowhere"), ("self", "a loop")])
def test_a_symlink_as_out_is_not_replaced_without_force(tmp_path, capsys, monkeypatch, link, state):
    monkeypatch.chdir(tmp_path)
    os.symlink(link if link != "self" else "b.obj", tmp_path / "b.obj")
    assert cli.main(["pose", "--angle", "elbow_l.flexion=30deg", "--out", "b.obj"]) == 2
    assert capsys.readouterr().err == (f"hitogata: error: --out b.obj: is a symbolic link ({state}); "
                                       "pass --force to replace the link\n")
    assert os.path.islink(tmp_path / "b.obj")


@pytest.mark.parametrize("argv, out", [
    (["body", "--out", "b.glb"], "b.glb"),
    (["body", "--size-chart", "women_example", "--out", "sizes"], "sizes"),
    (["motion", "export", "rectus_stretch", "--out", "m.bvh"], "m.bvh"),
])
def test_a_full_disk_is_one_line_and_leaves_nothing(tmp_path, argv, out):
    proc = start(argv, tmp_path, limit_bytes=4096)  # every file written stops at 4 kB, as on a full disk
    _, err = proc.communicate()
    assert proc.returncode == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    assert lines[0].startswith(f"hitogata: error: {out}") and "cannot write (File too large); nothing written" in lines[0]
    assert files_in(tmp_path) == []


def test_files_written_together_are_both_there_or_neither(tmp_path):
    write_files_together({tmp_path / "f.glb": b"body", tmp_path / "f.json": b"{}"})
    assert files_in(tmp_path) == ["f.glb", "f.json"]
    with pytest.raises(HitogataError):  # the second cannot be written: the first is not renamed in either
        write_files_together({tmp_path / "g.glb": b"body", tmp_path / "missing" / "g.json": b"{}"})
    assert files_in(tmp_path) == ["f.glb", "f.json"]


@pytest.mark.parametrize("argv", [
    ["body", "--size-chart", "women_example"],
    ["ease", "--motions", "reach,sit,squat"],
    ["fit-report", "--motions", "reach,sit"],
    ["modes", "--pictures", "0"],
], ids=lambda argv: argv[0])
def test_sigterm_during_a_folder_command_leaves_nothing(tmp_path, argv):
    """SIGTERM while the command works (its staging folder made, seconds of work ahead): exit 143, nothing left."""
    proc = start([*argv, "--out", "results"], tmp_path)
    try:
        assert wait_for(lambda: staging_exists(tmp_path, proc))
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate()
    finally:
        proc.kill()
    assert proc.returncode == 143, err
    assert err.strip().splitlines()[-1] == "hitogata: terminated; nothing written"
    assert files_in(tmp_path) == []


def test_a_later_run_removes_what_a_killed_one_left(tmp_path):
    """SIGKILL cannot be caught: its staging folder stays, and the next run of the same output removes it."""
    (tmp_path / "s.toml").write_text(LONG_SCENARIO)
    proc = start(["simulate", "s.toml", "--out", "results"], tmp_path)
    try:
        assert wait_for(lambda: staging_exists(tmp_path, proc))
        proc.kill()
        proc.wait()
    finally:
        proc.kill()
    assert any(p.name.startswith(".results.partial") for p in tmp_path.iterdir())  # and its lock file
    with output_lock(tmp_path / "results"):
        pass
    assert files_in(tmp_path) == ["s.toml"]
