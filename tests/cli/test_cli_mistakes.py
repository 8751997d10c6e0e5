"""Every mistake a one-line answer: exit 2, one line on stderr, no traceback, nothing written.

One test per bad input of issue 14, each run through `hitogata.cli.main` in an
empty folder that must still be empty afterwards (hidden staging folders
included). Model building is replaced by a failure where the mistake must be
found before it, so "before the work" is checked by behaviour, not by time.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from hitogata import cli
from hitogata.motion.checks import checked_scenario
from hitogata.motion.scenario import load_scenario
from hitogata.errors import HitogataError
from waiting import wait_for

SCENARIO = """
[model]
element_size = "60mm"
modes = 4
[output]
files = ["glb"]
[[keyframe]]
time = "0.5s"
{channel}
"""


def files_in(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


def mistake(argv: list[str], capsys) -> str:
    """The one line a mistaken command prints; asserts exit status 2 and no traceback."""
    try:
        code = cli.main(argv)
    except SystemExit as exit_:  # argparse's own checks
        code = exit_.code
    err = capsys.readouterr().err
    assert code == 2, err
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    return lines[0]


@pytest.fixture
def here(tmp_path, monkeypatch):
    """An empty working folder; the test asserts it holds only what it put there."""
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.fixture
def no_model(monkeypatch):
    """Building an elastic model fails the test: the mistake must be found before."""
    def refuse(*_, **__):
        raise AssertionError("the model was built before the mistake was found")

    import hitogata.commands.modes as modes
    import hitogata.simulation.run as run

    monkeypatch.setattr(modes, "cached_elastic_model", refuse)
    monkeypatch.setattr(run, "build_dynamics", refuse)


GLB_HEADER = b"glTF\x02\x00\x00\x00"


@pytest.mark.parametrize("content", [
    b"", GLB_HEADER[:4], GLB_HEADER + b"\x00" * 992, os.urandom(1000),
    GLB_HEADER + b"\xff\xff\x00\x00JSON" + b"{" * 400_000,
], ids=["empty", "4-byte", "truncated-1kB", "random", "truncated-400kB"])
def test_measure_of_a_broken_glb_is_one_line(here, capsys, content):
    (here / "body.glb").write_bytes(content)
    line = mistake(["measure", "body.glb", "--out", "report"], capsys)
    assert line.startswith("hitogata: error: body.glb:") and "allowed a .glb written by hitogata" in line
    assert files_in(here) == ["body.glb"]


def test_measure_of_a_truncated_real_glb_is_one_line(here, capsys, female):
    from hitogata.export.body_files import write_body

    data = write_body(here / "whole.glb", female).read_bytes()
    for size in (1000, 400_000):
        (here / "body.glb").write_bytes(data[:size])
        line = mistake(["measure", "body.glb", "--out", "report"], capsys)
        assert "body.glb: not a readable GLB file" in line
    assert files_in(here) == ["body.glb", "whole.glb"]


FOLDER_COMMANDS = {
    "measure": ["measure"],
    "modes": ["modes", "--pictures", "0"],
    "simulate": ["simulate", "rectus_stretch"],
    "demo": ["demo"],
    "fit-report": ["fit-report", "--motions", "reach"],
    "ease": ["ease", "--motions", "reach"],
}
FILE_COMMANDS = {
    "body": (["body"], ".glb"),
    "pose": (["pose", "--muscle", "biceps_brachii_l=10%"], ".glb"),
    "skeleton": (["skeleton"], ".png"),
}


@pytest.mark.parametrize("command", FOLDER_COMMANDS)
def test_a_folder_output_naming_an_existing_file_is_refused(here, capsys, no_model, command):
    (here / "taken").write_text("mine")
    line = mistake([*FOLDER_COMMANDS[command], "--out", "taken"], capsys)
    assert line == "hitogata: error: --out taken: is a file; allowed a folder (new, empty, or with --force)"
    assert files_in(here) == ["taken"] and (here / "taken").read_text() == "mine"


@pytest.mark.parametrize("command", FOLDER_COMMANDS)
def test_a_folder_output_that_is_not_empty_needs_force(here, capsys, no_model, command):
    (here / "results").mkdir()
    (here / "results" / "old.txt").write_text("mine")
    line = mistake([*FOLDER_COMMANDS[command], "--out", "results"], capsys)
    assert "--out results: the folder is not empty; name a new folder or pass --force" in line
    assert files_in(here) == ["results", "results/old.txt"]


@pytest.mark.parametrize("command", FILE_COMMANDS)
def test_a_file_output_naming_an_existing_file_needs_force(here, capsys, command):
    argv, suffix = FILE_COMMANDS[command]
    (here / f"out{suffix}").write_text("mine")
    line = mistake([*argv, "--out", f"out{suffix}"], capsys)
    assert line == f"hitogata: error: --out out{suffix}: the file exists; pass --force to write over it"
    assert (here / f"out{suffix}").read_text() == "mine"


@pytest.mark.parametrize("command", [*FOLDER_COMMANDS, *FILE_COMMANDS])
def test_an_output_that_cannot_be_written_is_refused_before_the_work(here, capsys, no_model, command):
    argv, suffix = FILE_COMMANDS.get(command, (FOLDER_COMMANDS.get(command), ""))
    line = mistake([*argv, "--out", f"/proc/x{suffix}"], capsys)
    assert line.startswith(f"hitogata: error: --out /proc/x{suffix}: cannot write in /proc")
    assert files_in(here) == []


def test_ease_writes_through_a_staging_folder(here, capsys, monkeypatch):
    """`hitogata ease` as every folder command: into a hidden staging folder, nothing left when it fails."""
    import hitogata.commands.ease as ease

    def stop(args):
        assert sorted(p.name for p in here.iterdir()) == [".out.lock", args.workdir.name]  # the lock held meanwhile
        assert args.workdir.name.startswith(".out.partial")
        raise HitogataError("stopped in the middle")

    monkeypatch.setattr(ease, "body_from_args", stop)
    assert mistake(["ease", "--motions", "reach", "--out", "out"], capsys) == "hitogata: error: stopped in the middle"
    assert files_in(here) == []
    line = mistake(["ease", "--motions", "nowhere"], capsys)  # the default --out ease/ is checked as well
    assert line.startswith("hitogata: error: --motions: 'nowhere'; allowed")
    assert files_in(here) == []


def test_an_empty_output_name_is_refused(here, capsys):
    assert mistake(["demo", "--out", ""], capsys) == "hitogata: error: --out '': allowed a folder name"
    assert files_in(here) == []


def test_a_folder_given_as_the_scenario_is_refused(here, capsys):
    (here / "scenario").mkdir()
    line = mistake(["simulate", "scenario", "--out", "results"], capsys)
    assert line == "hitogata: error: argument scenario: scenario: is a folder; allowed a file (.toml)"
    assert files_in(here) == ["scenario"]


@pytest.mark.parametrize("channel, expected", [
    ("contractions = { rectus_abdominus_l = \"5%\" }",
     "s.toml: [[keyframe]] 1.contractions.rectus_abdominus_l = '5%': no muscle 'rectus_abdominus_l'; "
     "did you mean rectus_abdominis_l"),
    ("angles = { \"knee_r.flexon\" = \"20deg\" }",
     "s.toml: [[keyframe]] 1.angles.knee_r.flexon = '20deg': no joint angle 'knee_r.flexon'; "
     "did you mean knee_r.flexion"),
    ("angles = { knee_r.flexion = \"200deg\" }",
     "s.toml: [[keyframe]] 1.angles.knee_r.flexion = '200deg': beyond the joint's range (shank_r.flexion); allowed"),
    ("contractions = { biceps_brachii_l = 25 }",
     "s.toml: [[keyframe]] 1.contractions.biceps_brachii_l: 25: a contraction is a fraction of the rest length, "
     "allowed between -1 and 1; did you mean 25%?"),
])
def test_a_scenario_mistake_blames_the_file_and_keyframe_before_any_model(here, capsys, no_model, channel, expected):
    (here / "s.toml").write_text(SCENARIO.format(channel=channel))
    line = mistake(["simulate", "s.toml", "--out", "results"], capsys)
    assert line.startswith(f"hitogata: error: {expected}")
    assert files_in(here) == ["s.toml"]


def test_a_scenario_body_outside_the_range_blames_the_file(here, capsys, no_model):
    (here / "s.toml").write_text('[body]\nstature = "230cm"\nmass = "60kg"\n' + SCENARIO.format(channel=""))
    line = mistake(["simulate", "s.toml", "--out", "results"], capsys)
    assert line == "hitogata: error: s.toml: [body]: stature 230.0 cm: allowed 140–210 cm"


def test_the_command_lines_spelling_is_accepted_in_a_scenario(here):
    (here / "s.toml").write_text(SCENARIO.format(channel='angles = { knee_r.flexion = "20deg", "elbow.flexion" = 10 }'))
    scenario, _ = checked_scenario(load_scenario(here / "s.toml"))
    names = sorted(c.name for c in scenario.timeline.channels)
    assert names == ["forearm_l.flexion", "forearm_r.flexion", "shank_r.flexion"]


def test_view_does_not_serve_a_missing_sequence(here, capsys, monkeypatch):
    import hitogata.viewer.app as app

    monkeypatch.setattr(app, "serve", lambda *_, **__: pytest.fail("served"))
    line = mistake(["view", "--play", "missing.npz"], capsys)
    assert line == ("hitogata: error: argument --play: missing.npz: no such file or folder; "
                    "allowed a file (.npz, .toml) or a folder")


def test_view_needs_the_whole_garment_before_serving(here, capsys, monkeypatch):
    import hitogata.viewer.app as app

    monkeypatch.setattr(app, "serve", lambda *_, **__: pytest.fail("served"))
    line = mistake(["view", "--garment-ease=-15%"], capsys)
    assert line == "hitogata: error: --garment-ease and --fabric: give both (e.g. --garment-ease -15% --fabric 400N/m)"


def test_body_options_that_do_not_apply_are_refused(here, capsys):
    (here / "body.glb").write_bytes(b"glTF")
    line = mistake(["measure", "body.glb", "--stature", "180cm", "--out", "report"], capsys)
    assert line == ("hitogata: error: --stature 180cm: does not apply here (the body comes from body.glb); "
                    "leave out --stature")
    assert files_in(here) == ["body.glb"]


def test_a_negative_mass_reaches_our_range_check(here, capsys):
    assert mistake(["body", "--mass", "-5kg", "--out", "b.glb"], capsys) == (
        "hitogata: error: --mass -5kg: allowed a positive mass, e.g. 58kg")
    assert files_in(here) == []


def test_a_bare_contraction_above_one_hints_at_percent(here, capsys):
    line = mistake(["pose", "--muscle", "biceps_brachii_l=25", "--out", "p.glb"], capsys)
    assert line.endswith("did you mean 25%?")
    assert files_in(here) == []


def test_ctrl_c_ends_with_one_line_130_and_no_folder(here, tmp_path):
    """SIGINT while the scenario runs: exit 130, one line, neither the folder nor its staging folder left."""
    # a long run (a minute of motion at 30 frames/s), so the signal lands while it works however busy the machine
    long_run = SCENARIO.replace("[output]", '[time]\nduration = "60s"\nrate = 30\n[output]')
    (here / "s.toml").write_text(long_run.format(channel='clinical = { "forearm_l.flexion" = "60deg" }'))
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(Path(cli.__file__).parents[1]),
                                                        os.environ.get("PYTHONPATH", "")])}
    proc = subprocess.Popen([sys.executable, "-m", "hitogata.cli", "simulate", "s.toml", "--out", "results"],
                            cwd=here, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        assert wait_for(lambda: any(p.name.startswith(".results.partial") for p in here.iterdir())
                        or proc.poll() is not None)
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate()
    finally:
        proc.kill()
    assert proc.returncode == 130, err
    assert err.strip() == "hitogata: interrupted; nothing written"
    assert files_in(here) == ["s.toml"]


def test_a_finished_run_renames_its_staging_folder(here, capsys):
    from hitogata.commands.paths import staged_folder

    with staged_folder(here / "out") as staging:
        (staging / "a.txt").write_text("a")
        assert not (here / "out").exists()
    assert files_in(here) == ["out", "out/a.txt"]
    with pytest.raises(HitogataError):
        with staged_folder(here / "other") as staging:
            (staging / "b.txt").write_text("b")
            raise HitogataError("stop")
    assert files_in(here) == ["out", "out/a.txt"]


@pytest.mark.parametrize("out", ["up.ply", "up.glb"])
def test_the_elastic_options_pick_dual_quaternion_skinning_themselves(here, capsys, monkeypatch, out):
    """`pose … --elastic --out up.ply` (the README's line) needs no --skinning: its checks pass and the
    elastic body is asked for (stopped here, before the minutes it takes)."""
    import hitogata.commands.pose as pose

    def stop(*_, **__):
        raise HitogataError("the elastic body is built now")

    monkeypatch.setattr(pose, "elastic_dynamics", stop)
    line = mistake(["pose", "--angle", "shoulder.flexion=150deg", "--elastic", "--out", out], capsys)
    assert line == "hitogata: error: the elastic body is built now"
    line = mistake(["pose", "--angle", "elbow.flexion=20deg", "--elastic", "--skinning", "lbs", "--out", "up.ply"],
                   capsys)
    assert line.startswith("hitogata: error: --elastic --skinning lbs: the elastic body stands on dual-quaternion")
    assert files_in(here) == []


def test_a_stop_inside_an_import_waits_for_the_import():
    """Ctrl-C raised inside an import can be swallowed (trimesh's optional imports catch BaseException) or break
    the import machinery: there the stop is sent again a moment later instead of raised."""
    from types import SimpleNamespace

    def frame(filename, back=None):
        return SimpleNamespace(f_code=SimpleNamespace(co_filename=filename), f_back=back)

    importing = frame("/lib/trimesh/exchange/load.py", frame("<frozen importlib._bootstrap>", frame("cli.py")))
    assert cli._importing(importing) and not cli._importing(frame("/lib/numpy/core.py", frame("cli.py")))


def test_a_fit_that_comes_no_closer_than_25_mm_writes_no_body(here, capsys, monkeypatch, female):
    """A scan shaped like a person that the model cannot follow (median 466 mm, as a ball gave) is refused."""
    from types import SimpleNamespace

    import trimesh

    import hitogata.made_to_measure.scan_fit as fit

    trimesh.Trimesh(female.vertices, female.faces, process=False).export(here / "s.ply")
    monkeypatch.setattr(fit, "fit_scan", lambda *_, **__: SimpleNamespace(model_error=SimpleNamespace(median=0.466)))
    line = mistake(["fit", "s.ply", "--sex", "female", "--out", "f.glb"], capsys)
    assert line == ("hitogata: error: s.ply: the body model comes no closer than a median 466 mm to the scan; allowed "
                    "a scan of a standing person (a fit comes within 25 mm); nothing written")
    assert files_in(here) == ["s.ply"]
