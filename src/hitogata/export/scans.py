"""Read a body scan (OBJ or PLY, triangle mesh or point cloud) with trimesh."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from hitogata.errors import HitogataError
from hitogata.made_to_measure.scan_fit.scan import Scan, make_scan

SCAN_SUFFIXES = (".obj", ".ply")


def read_scan(path: str | os.PathLike, unit: str | None = None) -> Scan:
    """The scan in a file, in metres (`unit` "mm"/"m", or None: decided from its extent).

    A triangle mesh keeps its triangles (area-even sampling, planar sections);
    anything else — a point cloud, a mesh without faces — is read as points.
    A file trimesh cannot read is a one-line error.
    """
    import trimesh

    path = Path(path)
    if path.suffix.lower() not in SCAN_SUFFIXES:
        raise HitogataError(f"{path}: unknown scan file suffix {path.suffix!r}; allowed: {', '.join(SCAN_SUFFIXES)}")
    try:
        loaded = trimesh.load(path, process=False, force=None)
    except Exception as err:  # trimesh raises many kinds on a broken file
        reason = str(err).splitlines()[0][:120] if str(err) else type(err).__name__
        raise HitogataError(f"{path}: not a readable scan ({reason}); allowed an OBJ or PLY mesh or point cloud"
                            ) from None
    if isinstance(loaded, trimesh.Scene):
        geometries = list(loaded.geometry.values())
        if len(geometries) != 1:
            raise HitogataError(f"{path}: {len(geometries)} objects; allowed one mesh or point cloud")
        loaded = geometries[0]
    points = np.asarray(getattr(loaded, "vertices", np.empty((0, 3))), dtype=np.float64)
    faces = getattr(loaded, "faces", None)
    faces = None if faces is None or len(faces) == 0 else np.asarray(faces, dtype=np.int64)
    return make_scan(points, faces, str(path), unit)
