"""The shipped MakeHuman data, loaded once into arrays ready for blending.

The file `data/mpfb2_adult.npz` is made by `tools/convert_mpfb2.py` from the CC0
MakeHuman (MPFB2) data; `docs/data.md` says what it holds. `data/mpfb2_child.npz`
holds MakeHuman's baby and child macro targets, loaded only for a body younger
than 18 (`load_child_targets`). Each is read through its inflated copy in the disk cache
(`hitogata.disk_cache`, keyed by the shipped file's digest): reading that takes a fifth of the
time of inflating the shipped file, which every process building a body otherwise pays.
"""

from __future__ import annotations

import hashlib
import io
from dataclasses import dataclass
from functools import cache
from importlib import resources

import numpy as np
import scipy.sparse as sp

DATA_FILE = "mpfb2_adult.npz"
CHILD_DATA_FILE = "mpfb2_child.npz"
INFLATED = "body-assets"  # the disk cache's entry kind of a data file's inflated copy


@dataclass(frozen=True, eq=False)
class Assets:
    """Base mesh, rig, weights and macro targets, in metres and the body frame.

    Vertex numbering: the first `n_surface` vertices are the skin; the rest are
    joint cubes and helper vertices that only place the rig's joints. The skin
    surface adds one cap centre per pocket loop after all of them.
    """

    base_vertices: np.ndarray  # (N, 3) metres
    n_surface: int
    triangles: np.ndarray  # (F, 3) into the skin vertices (cap centres included)
    cap_loops: tuple[np.ndarray, ...]  # vertex loops whose means are the cap centres
    bone_names: tuple[str, ...]
    bone_parents: np.ndarray  # (B,) -1 for the root
    joint_regressor: sp.csr_matrix  # (2B, N): heads then tails = regressor @ vertices
    skin_weights: sp.csr_matrix  # (S, B) over the skin vertices, rows sum to 1
    target_names: tuple[str, ...]
    targets: sp.csc_matrix  # (3N, T) metres; column t is target t's offsets, xyz interleaved

    @property
    def n_vertices(self) -> int:
        return len(self.base_vertices)


def skin_points(assets: Assets, vertices: np.ndarray) -> np.ndarray:
    """The skin surface's vertices: the surface ones plus a centre for each pocket cap."""
    caps = np.array([vertices[loop].mean(axis=0) for loop in assets.cap_loops])
    return np.concatenate([vertices[: assets.n_surface], caps])


def _triangles(quads: np.ndarray, loops: tuple[np.ndarray, ...], n_surface: int) -> np.ndarray:
    """Split quads into triangles and close each pocket loop with a fan round its centre.

    The loops run the way the quads traverse their boundary edges, so the caps
    traverse them backwards and the surface stays consistently oriented.
    """
    tris = [quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]]
    for k, loop in enumerate(loops):
        centre = np.full(len(loop), n_surface + k)
        tris.append(np.stack([np.roll(loop, -1), loop, centre], axis=1))
    return np.concatenate(tris).astype(np.int64)


def _cap_weights(rows: sp.csr_matrix, loops: tuple[np.ndarray, ...]) -> sp.csr_matrix:
    """Skin weights of the cap centres: the mean of their loop's weights."""
    caps = [sp.csr_matrix(rows[loop].mean(axis=0)) for loop in loops]
    return sp.vstack([rows, *caps]).tocsr()


def _read(name: str) -> dict[str, np.ndarray]:
    """The arrays of the data file `name`: from its inflated copy in the disk cache, made on the first read
    (the cache off: from the file itself)."""
    from hitogata import disk_cache  # on first use: it imports the atomic writer, which computation does not load

    packed = resources.files("hitogata").joinpath("data", name).read_bytes()
    key = {"file": name, "sha256": hashlib.sha256(packed).hexdigest()}
    return disk_cache.cached(INFLATED, key, lambda: _inflated(packed), dict, dict, None)


def _inflated(packed: bytes) -> dict[str, np.ndarray]:
    """The arrays of a compressed npz file's bytes."""
    with np.load(io.BytesIO(packed), allow_pickle=False) as stored:
        return dict(stored)


def _target_matrix(d: dict[str, np.ndarray], n_vertices: int) -> tuple[tuple[str, ...], sp.csc_matrix]:
    """Target names and their (3N, T) offsets in metres, from a data file's target arrays."""
    # int32 indices, scipy's own for this size: given int64 it would copy and check all 6 M of them
    vid = d["target_vertex"]  # sorted within each target
    rows = np.empty((len(vid), 3), dtype=np.int32)  # x, y, z of each vertex: 3v, 3v+1, 3v+2 (column by column:
    np.multiply(vid, 3, out=rows[:, 0], dtype=np.int32)  # a fifth of the time of numpy's broadcasting here)
    np.add(rows[:, 0], 1, out=rows[:, 1])
    np.add(rows[:, 0], 2, out=rows[:, 2])
    offsets = d["target_offset"].ravel() * float(d["target_unit"])
    targets = sp.csc_matrix(
        (offsets, rows.ravel(), (3 * d["target_ptr"]).astype(np.int32)), shape=(3 * n_vertices, len(d["target_ptr"]) - 1)
    )
    return tuple(str(n) for n in d["target_names"]), targets


@cache
def load_child_targets() -> tuple[tuple[str, ...], sp.csc_matrix]:
    """MakeHuman's baby and child macro targets (names, (3N, T) offsets in metres), loaded once."""
    return _target_matrix(_read(CHILD_DATA_FILE), load_assets().n_vertices)


@cache
def load_assets() -> Assets:
    """Load the data file once per process."""
    d = _read(DATA_FILE)
    n_surface = int(d["n_surface"])
    n_vertices = len(d["base_vertices"])
    ptr = d["cap_loop_ptr"]
    loops = tuple(d["cap_loops"][a:b].astype(np.int64) for a, b in zip(ptr[:-1], ptr[1:]))
    bones = tuple(str(n) for n in d["bone_names"])

    regressor = sp.csr_matrix(
        (d["regressor_weights"], (d["regressor_rows"], d["regressor_cols"])),
        shape=(2 * len(bones), n_vertices),
    )
    weights = sp.csr_matrix(
        (d["weight_values"].astype(np.float64), (d["weight_rows"], d["weight_cols"])),
        shape=(n_surface, len(bones)),
    )
    weights = _cap_weights(weights, loops)
    weights = sp.diags(1.0 / np.asarray(weights.sum(axis=1)).ravel()) @ weights

    target_names, targets = _target_matrix(d, n_vertices)
    skin_weights = weights.tocsr()
    # canonical once (sorted indices): scipy sorts a matrix in place on its first min/max and the like, so the
    # shared weights' sums (every body's skinning) took the order of whatever had asked first (round-off, but
    # enough to turn the contact's yes/no decisions in a test run after it)
    skin_weights.sum_duplicates()
    return Assets(
        base_vertices=d["base_vertices"],
        n_surface=n_surface,
        triangles=_triangles(d["quads"].astype(np.int64), loops, n_surface),
        cap_loops=loops,
        bone_names=bones,
        bone_parents=d["bone_parents"].astype(np.int64),
        joint_regressor=regressor,
        skin_weights=skin_weights,
        target_names=target_names,
        targets=targets,
    )
