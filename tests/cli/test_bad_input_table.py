"""A table of hostile inputs, one case per reader and command argument: one line, exit 2, nothing left.

Every case runs `hitogata.cli.main` in an empty folder holding only its input
files and must end with exit status 2 and one line `hitogata: error: …` of at
most 300 characters that names the file, entry or value (the case's expected
words), no traceback, and the folder as it was (no output, no staging folder,
no temporary file, no lock). The file readers are fed what breaks a naive
reader: sizes and counts far beyond the file, nesting 100,000 deep, values of
the wrong kind, NaN and out-of-range physical quantities. None builds a model:
each mistake is found before the work.
"""

from __future__ import annotations

import json
import re
import struct
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from hitogata import cli
from samples import SMALL_BVH as GOOD_BVH

LINE_LIMIT = 300


def deep_bvh(depth: int) -> str:
    joints = "".join(f"JOINT j{i}\n{{\nOFFSET 0 1 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n" for i in range(1, depth))
    values = " ".join(["0"] * 3 * depth)
    return (f"HIERARCHY\nROOT j0\n{{\nOFFSET 0 0 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n{joints}"
            f"{'}' * depth}\nMOTION\nFrames: 1\nFrame Time: 0.04\n{values}\n")


def glb(document: object, blob: bytes = b"") -> bytes:
    """A GLB container around a JSON document (any JSON text when a str) and a binary chunk."""
    text = (document if isinstance(document, str) else json.dumps(document)).encode()
    text += b" " * (-len(text) % 4)
    blob += b"\0" * (-len(blob) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(blob), 0x004E4942) + blob
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


def edited_body_glb(change: Callable[[dict], None]) -> Callable[[Path], bytes]:
    """A real body file (`write_body`) with its JSON document changed."""
    def make(folder: Path) -> bytes:
        from hitogata.body import Body
        from hitogata.export.body_files import write_body
        from hitogata.export.glb_read import read_glb

        path = write_body(folder / "real.glb", Body.from_measurements(sex="female"))
        document, blob = read_glb(path)
        path.unlink()
        change(document)
        return glb(document, blob or b"")
    return make


def set_extra(key: str, value: object) -> Callable[[dict], None]:
    def change(document: dict) -> None:
        node = next(n for n in document["nodes"] if n.get("skin") is not None)
        node["extras"][key] = value
    return change


def huge_count(document: dict) -> None:
    document["accessors"][0]["count"] = 10**12


def sequence_npz(**changes: object) -> Callable[[Path], bytes]:
    def make(folder: Path) -> bytes:
        arrays = {"times": np.array([0.0, 0.1]), "vertices": np.zeros((2, 10, 3), np.float32),
                  "joints": np.zeros((2, 5, 3)), "shape": np.array('{"sex": 0.0}'), "density": np.array(1000.0)}
        arrays.update(changes)  # type: ignore[arg-type]
        np.savez(folder / "made.npz", **arrays)
        data = (folder / "made.npz").read_bytes()
        (folder / "made.npz").unlink()
        return data
    return make


SCENARIO_HEAD = '[model]\nelement_size = "60mm"\nmodes = 4\n'
# id: (input files {name: bytes, text or a maker of bytes}, argv, words the line must hold)
CASES: dict[str, tuple[dict[str, object], list[str], list[str]]] = {
    # BVH (motion import and a scenario's [timeline] bvh)
    "bvh-nested-5000": ({"m.bvh": deep_bvh(5000)}, ["motion", "import", "m.bvh", "--out", "m.toml"],
                        ["m.bvh: line", "nested 65 deep", "at most 64 levels"]),
    "bvh-zero-offsets": ({"m.bvh": lambda folder: re.sub(r"OFFSET [-\d. ]+", "OFFSET 0 0 0", exported_bvh(folder))},
                         ["motion", "import", "m.bvh", "--out", "m.toml"], ["m.bvh:", "OFFSET is zero"]),
    "bvh-1e300-offsets": ({"m.bvh": GOOD_BVH.replace("OFFSET 0 10 0", "OFFSET 1e300 1e300 1e300")},
                          ["motion", "import", "m.bvh", "--out", "m.toml"], ["m.bvh: line 8", "Spine OFFSET", "±100000"]),
    "bvh-20000-frames": ({"m.bvh": GOOD_BVH.replace("Frames: 2\nFrame Time: 0.04", "Frames: 20000\nFrame Time: 0.0333")},
                         ["motion", "import", "m.bvh", "--out", "m.toml"], ["m.bvh: line", "666 s", "at most 600 s"]),
    "bvh-a-private-file": ({"m.bvh": "root:x:0:0:root:/root:/bin/bash\n" * 3}, ["motion", "import", "m.bvh", "--out", "m.toml"],
                           ["m.bvh: line 1: not a BVH file"]),
    "bvh-one-800kB-word": ({"m.bvh": "HIERARCHY ROOT " + "0" * 800_000}, ["motion", "import", "m.bvh", "--out", "m.toml"],
                           ["m.bvh: line 1", "800,000 characters"]),
    "bvh-long-joint-name": ({"m.bvh": GOOD_BVH.replace("JOINT Spine", "JOINT " + "S" * 5000)},
                            ["motion", "import", "m.bvh", "--out", "m.toml"], ["m.bvh: line 6", "joint name"]),
    "scenario-bvh-absolute": ({"s.toml": SCENARIO_HEAD + '[timeline]\nbvh = "/etc/passwd"\n'},
                              ["simulate", "s.toml", "--out", "r"], ["s.toml: [timeline].bvh: '/etc/passwd'", "no absolute"]),
    "scenario-bvh-parent": ({"s.toml": SCENARIO_HEAD + '[timeline]\nbvh = "../m.bvh"\n'},
                            ["simulate", "s.toml", "--out", "r"], ["s.toml: [timeline].bvh: '../m.bvh'", "no '..'"]),
    "scenario-joint-map-absolute": ({"s.toml": SCENARIO_HEAD + '[timeline]\nbvh = "m.bvh"\njoint_map = "/x/map.toml"\n',
                                     "m.bvh": GOOD_BVH}, ["simulate", "s.toml", "--out", "r"],
                                    ["s.toml: [timeline].joint_map: '/x/map.toml'"]),
    "toml-nested-100000": ({"s.toml": "a = " + "[" * 100_000 + "]" * 100_000 + "\n"}, ["simulate", "s.toml", "--out", "r"],
                           ["s.toml: not valid TOML: arrays or tables nested too deep"]),
    "toml-study-nested-100000": ({"s.toml": "a = " + "[" * 100_000 + "]" * 100_000 + "\n"},
                                 ["study", "s.toml", "--out", "r"], ["s.toml: not valid TOML: arrays or tables nested"]),
    "toml-5000-digit-integer": ({"s.toml": "title = " + "9" * 5000 + "\n"}, ["simulate", "s.toml", "--out", "r"],
                                ["s.toml: not a usable TOML file", "4300 digits"]),
    "toml-5MB-line": ({"s.toml": 'title = "' + "x" * 5_000_000 + "\n"}, ["simulate", "s.toml", "--out", "r"],
                      ["s.toml: not valid TOML: Illegal character"]),
    # GLB body files (measure, pose --body)
    "glb-accessor-count-1e12": ({"b.glb": edited_body_glb(huge_count)}, ["measure", "b.glb", "--out", "r"],
                                ["b.glb: not a readable GLB file", "accessor 0", "1000000000000 items"]),
    "glb-json-nested-100000": ({"b.glb": glb("[" * 100_000 + "]" * 100_000)}, ["measure", "b.glb", "--out", "r"],
                               ["b.glb: not a readable GLB file", "nested too deep"]),
    "glb-density-heavy": ({"b.glb": edited_body_glb(set_extra("density", "heavy"))}, ["measure", "b.glb", "--out", "r"],
                          ["b.glb: extras 'density' 'heavy' kg/m³", "900–1100"]),
    "glb-density-negative": ({"b.glb": edited_body_glb(set_extra("density", -1000))},
                             ["pose", "--body", "b.glb", "--angle", "elbow_l.flexion=30deg", "--out", "p.obj"],
                             ["b.glb: extras 'density' -1000 kg/m³"]),
    "glb-density-nan": ({"b.glb": edited_body_glb(set_extra("density", float("nan")))},
                        ["pose", "--body", "b.glb", "--angle", "elbow_l.flexion=30deg", "--out", "p.obj"],
                        ["b.glb: extras 'density' nan kg/m³"]),
    # sequences (.npz)
    "npz-shape-not-json": ({"s_sequence.npz": sequence_npz(shape=np.array("{not json"))},
                           ["measure", "s_sequence.npz", "--out", "r"], ["s_sequence.npz: 'shape': not JSON"]),
    "npz-zero-frames": ({"s_sequence.npz": sequence_npz(times=np.zeros(0), vertices=np.zeros((0, 10, 3)))},
                        ["measure", "s_sequence.npz", "--out", "r"], ["s_sequence.npz: 'times' of shape (0,)"]),
    "npz-text-times": ({"s_sequence.npz": sequence_npz(times=np.array(["a", "b"]))},
                       ["measure", "s_sequence.npz", "--out", "r"], ["s_sequence.npz: array 'times'", "allowed numbers"]),
    "npz-not-a-zip": ({"s_sequence.npz": b"\0" * 5000}, ["measure", "s_sequence.npz", "--out", "r"],
                      ["s_sequence.npz: not a readable .npz file"]),
    # size charts (CSV)
    "csv-200kB-field": ({"c.csv": "size,stature_cm\n\"" + "1" * 200_000 + "\",160\n"},
                        ["body", "--size-chart", "c.csv", "--out", "sizes"], ["c.csv: row", "not CSV", "field larger"]),
    "csv-2MiB": ({"c.csv": "size,stature_cm\n" + "M,160\n" * 400_000}, ["body", "--size-chart", "c.csv", "--out", "sizes"],
                 ["c.csv: 2.3 MiB", "at most 1 MiB"]),
    "csv-long-size-name": ({"c.csv": "size,stature_cm\n" + "M" * 300 + ",160\n"},
                           ["body", "--size-chart", "c.csv", "--out", "sizes"], ["c.csv: row 2, column size", "up to 40"]),
    "size-chart-out-as-a-file": ({"c.csv": "size,stature_cm\nM,160\n"}, ["body", "--size-chart", "c.csv", "--out", "sizes.glb"],
                                 ["--out sizes.glb: names a .glb file", "e.g. sizes"]),
    # scans (fit)
    "scan-a-ball": ({"ball.ply": lambda _: __import__("trimesh").creation.icosphere(4, radius=0.9).export(file_type="ply")},
                    ["fit", "ball.ply", "--sex", "female", "--out", "f.glb"], ["ball.ply: not shaped like a standing person"]),
    "scan-metres-declared-mm": ({"s.ply": lambda folder: scan_ply(1.0)}, ["fit", "s.ply", "--sex", "female", "--units", "mm",
                                                                          "--out", "f.glb"],
                                ["s.ply: --units mm: the scan spans 0.00", "is the file in m?"]),
    "scan-mm-declared-m": ({"s.ply": lambda folder: scan_ply(1000.0)}, ["fit", "s.ply", "--sex", "female", "--units", "m",
                                                                        "--out", "f.glb"],
                           ["s.ply: --units m: the scan spans 1", "is the file in mm?"]),
    "scan-random-bytes": ({"s.ply": bytes(range(256)) * 40}, ["fit", "s.ply", "--sex", "female", "--out", "f.glb"],
                          ["s.ply: not a readable scan"]),
    "scan-ply-claims-1e12-vertices": ({"s.ply": b"ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\n"
                                                b"property float x\nproperty float y\nproperty float z\nend_header\n"
                                                + b"\0" * 1200},
                                      ["fit", "s.ply", "--sex", "female", "--out", "f.glb"], ["s.ply: "]),
    "scan-obj-nan-and-few-points": ({"s.obj": "v nan nan nan\n" * 10 + "v 0 0 0\nv 0 1.7 0\nv 0.3 0 0.2\n"},
                                    ["fit", "s.obj", "--sex", "female", "--out", "f.glb"],
                                    ["s.obj: 3 points; allowed a scan of at least 2000 points"]),
    # command arguments
    "stature-1e308cm": ({}, ["body", "--stature", "1e308cm", "--mass", "60kg", "--out", "b.glb"], ["stature 1e+308 cm"]),
    "option-abbreviated": ({}, ["body", "--stat", "170cm", "--out", "b.glb"], ["unrecognized arguments: --stat 170cm"]),
    "unknown-scenario-name": ({}, ["simulate", "reach", "--out", "r"],
                              ["'reach': no such file; did you mean mobility_reach_forward?", "shipped name: elbow_flexion_body"]),
    "ease-rate-1e9": ({}, ["ease", "--motions", "reach", "--rate", "1e9", "--out", "e"], ["--rate 1e+09", "at most"]),
    "shoulder-flexion-and-abduction-180": ({}, ["pose", "--angle", "shoulder_l.flexion=180deg", "--angle",
                                                "shoulder_l.abduction=180deg", "--out", "p.obj"],
                                           ["shoulder_l.flexion 180°", "undo each other"]),
    "motion-import-over-a-file": ({"m.bvh": GOOD_BVH, "m.toml": "mine"}, ["motion", "import", "m.bvh", "--out", "m.toml"],
                                  ["--out m.toml: the file exists; pass --force"]),
    "motion-export-over-a-file": ({"m.bvh": "mine"}, ["motion", "export", "rectus_stretch", "--out", "m.bvh"],
                                  ["--out m.bvh: the file exists; pass --force"]),
    "study-memory-limit-1MiB": ({}, ["study", "example", "--out", "r", "--memory-limit", "1MiB"], ["at least 512 MiB"]),
}


def exported_bvh(folder: Path) -> str:
    """A shipped scenario's motion as `motion export` writes it (the skeleton's own joint names)."""
    assert cli.main(["motion", "export", "rectus_stretch", "--out", str(folder / "made.bvh")]) == 0
    text = (folder / "made.bvh").read_text()
    (folder / "made.bvh").unlink()
    return text


def scan_ply(scale: float) -> bytes:
    from hitogata.body import Body

    body = Body.from_measurements(sex="female")
    import trimesh

    return trimesh.Trimesh(body.vertices * scale, body.faces, process=False).export(file_type="ply")


def files_in(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() if p.is_file() else b"" for p in sorted(folder.rglob("*"))}


@pytest.mark.parametrize("case", CASES)
def test_a_hostile_input_is_one_short_line_and_leaves_nothing(case, tmp_path, monkeypatch, capsys):
    files, argv, words = CASES[case]
    for name, content in files.items():
        made = content(tmp_path) if callable(content) else content
        path = tmp_path / name
        path.write_bytes(made.encode() if isinstance(made, str) else made)  # type: ignore[union-attr]
    before = files_in(tmp_path)
    monkeypatch.chdir(tmp_path)
    code = cli.main(argv)
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and "Traceback" not in err, err[:2000]
    line = lines[0]
    assert line.startswith("hitogata: error: ") and len(line) <= LINE_LIMIT, line
    for word in words:
        assert word in line, line
    assert files_in(tmp_path) == before
