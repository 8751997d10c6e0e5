"""Read a numpy .npz archive as a user's file: sizes bounded before anything is decompressed.

An .npz is a zip of .npy arrays; `np.load` would decompress whatever a member
claims. Here each member's declared size is checked against `MAX_BYTES` (all
members together) first, only numeric arrays (and strings, for a JSON entry)
are accepted, and every failure is one line naming the file and the entry.
"""

from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np

from hitogata.errors import HitogataError, excerpt

MAX_BYTES = 4 * 2**30  # all arrays together, uncompressed: 600 s of a whole-body sequence at 30 frames/s is ~2 GiB


def read_npz(path: Path, limit: int = MAX_BYTES) -> dict[str, np.ndarray]:
    """The arrays of an .npz file, by name; one line if it is not one or is larger than `limit` bytes unpacked."""
    try:
        with zipfile.ZipFile(path) as archive:
            size = sum(info.file_size for info in archive.infolist())
        if size > limit:
            raise HitogataError(f"{path}: {size / 2**30:.1f} GiB of arrays unpacked; allowed at most "
                                f"{limit / 2**30:.0f} GiB")
        with np.load(path, allow_pickle=False) as data:
            arrays = {name: data[name] for name in data.files}
    except HitogataError:
        raise
    except (OSError, ValueError, zipfile.BadZipFile, EOFError, KeyError) as exc:
        raise HitogataError(f"{path}: not a readable .npz file ({type(exc).__name__}: "
                            f"{excerpt(str(exc), 80)})") from None
    for name, array in arrays.items():
        if array.dtype.kind not in "biuf" and not (array.dtype.kind == "U" and array.ndim == 0):
            raise HitogataError(f"{path}: array {excerpt(name)} of type {array.dtype}; allowed numbers")
    return arrays
