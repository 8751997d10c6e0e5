"""VTU files (ParaView) through meshio, written atomically, with field data meshio's writer leaves out.

meshio (5.3) reads a VTU's `<FieldData>` but does not write it; ParaView shows
field data in its Information panel. So the file is written by meshio into a
scratch folder, the field data are inserted as ASCII arrays right after the
`<UnstructuredGrid>` tag, and the result is renamed over the target.

Names (regions, muscles) cannot travel as numbers: each becomes an array of
its own whose *name* is the name and whose value the label it stands for,
e.g. `region 2: viscera` = [2], so the legend is in the file itself.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path
from xml.sax.saxutils import quoteattr

import meshio
import numpy as np

from hitogata.export.atomic import write_bytes_atomically

_TYPES = {"f": "Float64", "i": "Int64", "u": "Int64", "b": "Int64"}


def label_arrays(kind: str, names: Sequence[str]) -> dict[str, np.ndarray]:
    """{'region 0: skin': [0], ...}: the names of integer labels, as field data."""
    return {f"{kind} {k}: {name}": np.array([k]) for k, name in enumerate(names)}


def _field_xml(field_data: Mapping[str, np.ndarray]) -> bytes:
    arrays = []
    for name, values in field_data.items():
        values = np.asarray(values)
        kind = _TYPES[values.dtype.kind]
        text = " ".join(repr(float(v)) if kind == "Float64" else str(int(v)) for v in values.ravel())
        shape = (f'NumberOfTuples="{len(values)}" NumberOfComponents="{values.shape[1]}"' if values.ndim == 2
                 else f'NumberOfTuples="{values.size}"')
        arrays.append(f'<DataArray type="{kind}" Name={quoteattr(name)} {shape} format="ascii">{text}</DataArray>')
    return ("<FieldData>" + "".join(arrays) + "</FieldData>").encode()


def write_vtu(path: str | os.PathLike, mesh: meshio.Mesh, field_data: Mapping[str, np.ndarray] | None = None
              ) -> Path:
    """Write `mesh` as a binary VTU with `field_data` (numbers; a 2-D array's rows are its tuples),
    atomically; return the path."""
    with tempfile.TemporaryDirectory() as scratch:
        temporary = Path(scratch) / "mesh.vtu"
        meshio.write(temporary, mesh, file_format="vtu", binary=True)
        data = temporary.read_bytes()
    if field_data:
        tag = b"<UnstructuredGrid>"
        at = data.index(tag) + len(tag)
        data = data[:at] + _field_xml(field_data) + data[at:]
    return write_bytes_atomically(path, data)
