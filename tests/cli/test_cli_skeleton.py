"""`hitogata skeleton`: the posed skeleton drawn front and side, in its skin on request."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from matplotlib.image import imread

pytest.importorskip("pyvista")

from hitogata.body import Body  # noqa: E402
from hitogata.cli import main  # noqa: E402
from hitogata.posing import poser_for  # noqa: E402
from hitogata.render.figures import bone_segments, skeleton_items  # noqa: E402
from hitogata.render.scene import Layer, Lines  # noqa: E402

SMALL = ["--height", "270"]


@pytest.fixture()
def female_args(female: Body, monkeypatch):
    monkeypatch.setattr("hitogata.commands.body_file.body_from_args", lambda args: female)
    return female


def test_picture_of_the_posed_skeleton(tmp_path: Path, female_args, capsys) -> None:
    bare, skin = tmp_path / "bare.png", tmp_path / "skin.png"
    pose = ["--muscle", "biceps_brachii_l=25%", "--angle", "knee_r.flexion=60deg"]
    assert main(["skeleton", *pose, *SMALL, "--out", str(bare)]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"{bare}: front, side views, ") and "biceps_brachii_l contracted 25.0%" in out
    assert main(["skeleton", *pose, *SMALL, "--skin", "--muscle-lines", "all", "--out", str(skin)]) == 0
    a, b = imread(bare), imread(skin)
    assert a.shape[0] == 270 and 150 < a.shape[1] < 400  # two views, each as wide as it needs
    assert a[..., :3].std() > 0.05 and a[..., :3].mean() > 0.7  # drawn, on a light background
    assert b[..., :3].mean() < a[..., :3].mean() - 0.02  # the skin covers much more of the picture


def test_figure_items(female: Body) -> None:
    posed = poser_for(female).pose(contractions={"biceps_brachii_l": 0.2})
    segments, radii = bone_segments(posed)
    assert len(segments) > 65 and np.all((radii > 0) & (radii <= 0.01))  # 65 parts and their ties to parents
    items = skeleton_items(posed, skin=True, muscles=["biceps_brachii_l"], other_muscles=True)
    lines = [i for i in items if isinstance(i, Lines)]
    assert [len(x.segments) for x in lines[1:]] == [113, 1]  # faded others, the given muscle bold
    assert isinstance(items[-1], Layer) and items[-1].opacity < 1


@pytest.mark.parametrize(
    "args,message",
    [
        (["--out", "skeleton.jpg"], "unknown file suffix '.jpg'; allowed: .png"),
        (["--height", "big", "--out", "s.png"], "--height 'big': allowed a whole number of pixels"),
        (["--views", "front,above", "--out", "s.png"], "--views 'front,above': allowed a comma-separated list"),
        (["--angle", "elbow_l.flex=1rad", "--out", "s.png"], "did you mean forearm_l.flexion"),
    ],
)
def test_bad_input_one_line_and_no_file(tmp_path: Path, female_args, capsys, monkeypatch, args, message) -> None:
    monkeypatch.chdir(tmp_path)
    assert main(["skeleton", *args]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("hitogata: error:") and "\n" not in err and message in err, err
    assert list(tmp_path.iterdir()) == []


def test_missing_gl_is_an_error_not_a_segfault(tmp_path: Path) -> None:
    env = {**os.environ, "LIBGL_DRIVERS_PATH": "/nonexistent"}
    env.pop("VTK_DEFAULT_OPENGL_WINDOW", None)
    out = tmp_path / "s.png"
    result = subprocess.run(
        [sys.executable, "-m", "hitogata.cli", "skeleton", "--out", str(out)],
        env=env, capture_output=True, text=True, timeout=120,
    )
    assert result.returncode == 2, result.stderr[-500:]
    err = result.stderr.strip()
    assert err.startswith("hitogata: error: offscreen rendering") and "\n" not in err
    assert "apt-get install -y libegl1 libegl-mesa0 libgl1-mesa-dri" in err
    assert not out.exists()
