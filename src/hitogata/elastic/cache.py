"""The elastic model of a body built once and kept on disk (`hitogata.disk_cache`), keyed by what it is built from.

The key holds the body (a digest of its vertices, triangles, rig, skinning weights,
density and sex: a body read from a file keys the same as one built from parameters
when they agree), every option of `build_elastic_model` (the materials by their
values, not their file's name), the package's version and a digest of its code
and data (a changed model or asset never reads an old entry), and `FORMAT`.
"""

from __future__ import annotations

import hashlib
import inspect
import json
import os
import time
from collections.abc import Mapping
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp

from hitogata import disk_cache
from hitogata.body.model import Body
from hitogata.elastic.materials import Materials, load_materials
from hitogata.elastic.model import ElasticModel, build_elastic_model
from hitogata.elastic.stored import from_arrays, to_arrays

FORMAT = 1  # raised when what an entry holds, or how, changes
MODEL = "elastic-model"  # the entry kind of a bare elastic model
CODE = "code-digest"  # the entry kind of the code digest of the package's files as they stand
SETTLED = 2.0  # s: files changed within this of the digest (a file system's clock is coarse) are not remembered


def model_options(**options: Any) -> dict[str, Any]:
    """`build_elastic_model`'s options, every default filled in and the materials read (a `Materials`)."""
    bound = inspect.signature(build_elastic_model).bind(None, **options)
    bound.apply_defaults()
    chosen = dict(bound.arguments)
    chosen.pop("body")
    materials = chosen["materials"]
    chosen["materials"] = materials if isinstance(materials, Materials) else load_materials(materials)
    return chosen


def model_key(body: Body, options: Mapping[str, Any]) -> dict[str, Any]:
    """The key of the elastic model of `body` built with `options` (`model_options`' form)."""
    plain = {name: _plain(value) for name, value in options.items() if name not in ("materials", "volume")}
    return {"format": FORMAT, "code": code_digest(), "body": body_digest(body),
            "materials": materials_values(options["materials"]), "options": plain}


def materials_values(table: Materials) -> dict[str, Any]:
    """The materials by value: each region's E (Pa), nu, rho (kg/m³), and the Rayleigh damping if given."""
    return {"regions": {name: [m.E, m.nu, m.rho] for name, m in sorted(table.regions.items())},
            "rayleigh": None if table.rayleigh is None else list(table.rayleigh)}


def body_digest(body: Body) -> str:
    """A digest of what the elastic model takes from a body: skin, rig, skinning weights, density, sex
    (found once per body)."""
    return body.prepared(_body_digest)


def _body_digest(body: Body) -> str:
    h = hashlib.sha256()
    weights = sp.csr_matrix(body.skin_weights)
    rig = body.rig
    for array in (body.all_vertices, body.faces, rig.heads, rig.tails, rig.parents, weights.data, weights.indices,
                  weights.indptr, np.array([body.density, body.params.sex])):
        h.update(np.ascontiguousarray(array).tobytes())
    h.update("\n".join(rig.names).encode())
    return h.hexdigest()


@lru_cache(maxsize=1)
def code_digest() -> str:
    """The package's version and a digest of its code and data files (so a changed checkout misses)."""
    import hitogata

    return package_digest(Path(hitogata.__file__).parent, str(hitogata.__version__))


def package_digest(package: Path, version: str) -> str:
    """`version` and a digest of the files in the folder `package` (bytecode left out).

    Remembered in the disk cache under every file's size, modification time and inode, as Python's own
    bytecode cache trusts a source's size and time: reading the package's 14 MB again costs a held pose
    ~0.05 s. Files changed within `SETTLED` seconds of the reading are not remembered (a write in the same
    tick of the file system's clock would keep the time)."""
    files = _package_files(package)
    stamps = [(name, info.st_size, info.st_mtime_ns, info.st_ino) for name, info in files]
    key = {"version": version, "files": hashlib.sha256(json.dumps(stamps).encode()).hexdigest()}
    remember = disk_cache.enabled()
    stored = disk_cache.load(CODE, key) if remember else None
    if stored is not None and "digest" in stored:
        return str(stored["digest"])
    started = time.time_ns()
    h = hashlib.sha256(version.encode())
    for name, _ in files:
        h.update(name.encode())
        h.update((package / name).read_bytes())
    digest = f"{version}+{h.hexdigest()[:16]}"
    if remember and max((info.st_mtime_ns for _, info in files), default=0) < started - SETTLED * 1e9:
        disk_cache.save(CODE, key, {"digest": np.array(digest)})
    return digest


def _package_files(package: Path) -> list[tuple[str, os.stat_result]]:
    """Every file of the package but bytecode (its path relative to `package`, in order, and its stat)."""
    found = []
    folders = [""]
    while folders:
        folder = folders.pop()
        with os.scandir(package / folder) as entries:
            for entry in entries:
                name = f"{folder}{entry.name}"
                if entry.is_dir():
                    if entry.name != "__pycache__":
                        folders.append(f"{name}/")
                elif entry.is_file():
                    found.append((name, entry.stat()))
    return sorted(found, key=lambda item: item[0])


def cached_elastic_model(body: Body, cache: bool | None = None, **options: Any) -> ElasticModel:
    """`build_elastic_model(body, **options)` read from the disk cache when it was built before (then stored);
    a model given its `volume` is built (a volume is not keyed)."""
    chosen = model_options(**options)
    if chosen["volume"] is not None:
        return build_elastic_model(body, **chosen)
    return disk_cache.cached(MODEL, model_key(body, chosen), lambda: build_elastic_model(body, **chosen), to_arrays,
                  from_arrays, cache)


def _plain(value: Any) -> Any:
    """An option as JSON: tuples as lists, numbers as floats."""
    if isinstance(value, (tuple, list)):
        return [_plain(v) for v in value]
    if isinstance(value, (np.integer, np.floating)):
        return value.item()
    return value
