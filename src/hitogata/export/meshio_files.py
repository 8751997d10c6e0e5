"""Finite-element meshes (VTU and the other meshio formats) written atomically.

meshio writes to a path, not to bytes: the mesh goes to a temporary sibling
of the target (same folder, so the rename cannot cross file systems) and is
renamed over it, so a reader never sees half a file.
"""

from __future__ import annotations

import os
import secrets
from pathlib import Path

import meshio

from hitogata.errors import HitogataError


def write_meshio(path: str | os.PathLike, mesh: meshio.Mesh, file_format: str | None = None) -> Path:
    """Write `mesh` to `path` (format from the suffix unless given; binary where the format has it)."""
    path = Path(path)
    if not path.parent.is_dir():
        raise HitogataError(f"{path}: cannot write, directory {path.parent} does not exist")
    temporary = path.with_name(f".{path.stem}.{secrets.token_hex(4)}{path.suffix}")
    try:
        meshio.write(temporary, mesh, file_format=file_format)
        os.replace(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)
    return path
