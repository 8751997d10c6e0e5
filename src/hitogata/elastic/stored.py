"""The elastic model as plain arrays and back, for the disk cache (`hitogata.disk_cache`).

A value is taken apart into numpy arrays (sparse matrices as their CSR arrays,
a pattern stored once when K and M share it) and a JSON tree of the rest:
numbers, strings, tuples, mappings, and the project's own frozen dataclasses,
named in `CLASSES`. Reading builds only those classes back from their fields:
nothing in a stored entry is code. A sparse matrix whose arrays the cache entry
holds back (`disk_cache.Entry`, deferred) comes back as a `DeferredMatrix`,
read when first used.
"""

from __future__ import annotations

import dataclasses
import json
import threading
from collections.abc import Callable, Mapping
from types import MappingProxyType
from typing import Any

import numpy as np
import scipy.sparse as sp

from hitogata.disk_cache import Entry
from hitogata.elastic.materials import Materials
from hitogata.elastic.model import ElasticModel
from hitogata.fem import Material
from hitogata.fem.modes import Modes
from hitogata.volume.integrity import MeshIntegrity
from hitogata.volume.model import VolumeModel, VolumeQuality
from hitogata.volume.repair import Repair

CLASSES: dict[str, type] = {cls.__name__: cls for cls in (ElasticModel, VolumeModel, VolumeQuality, MeshIntegrity,
                                                           Repair, Materials, Material, Modes)}
TREE = "tree"  # the array holding the JSON tree, beside the value's arrays


class DeferredMatrix(sp.csr_matrix):
    """A CSR matrix whose arrays are read when it is first used (any of its attributes asked for; one thread
    reads, any other asking meanwhile waits for it), then a CSR matrix like any other: a held posture never
    reads the whole body's stiffness and mass matrices."""

    def __init__(self, arg1: Callable[[], tuple[np.ndarray, np.ndarray, np.ndarray]] | Any, shape: Any = None,
                 *args: Any, **kwargs: Any) -> None:
        """arg1: what reads the arrays (data, indices, indptr) when the matrix is first used, `shape` its shape;
        otherwise (a matrix scipy makes from this one's arrays, as `csr_matrix`'s arguments) a CSR matrix."""
        if callable(arg1):
            self.__dict__.update(_read=arg1, _stored_shape=shape, _reading=threading.RLock())
        else:
            super().__init__(arg1, shape, *args, **kwargs)

    @property
    def arrays_read(self) -> bool:
        """Whether the arrays have been read."""
        return "_read" not in self.__dict__

    def __getattr__(self, name: str) -> Any:  # only for attributes not set: the first use reads the arrays
        state = self.__dict__
        reading = state.get("_reading")
        if reading is not None and not name.startswith("__"):
            with reading:
                read = state.pop("_read", None)
                if read is not None:
                    sp.csr_matrix.__init__(self, read(), shape=state["_stored_shape"])
            if name in state:
                return state[name]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def __reduce__(self) -> tuple[type, tuple]:  # pickled (to a Dask worker) as the plain matrix it is
        return sp.csr_matrix, ((self.data, self.indices, self.indptr), self.shape)


def to_arrays(value: Any, prefix: str = "") -> dict[str, np.ndarray]:
    """`value` as named arrays (names start with `prefix`), its JSON tree among them."""
    arrays: dict[str, np.ndarray] = {}
    tree = _encode(value, prefix, arrays, [])
    arrays[prefix + TREE] = np.array(json.dumps(tree))
    return arrays


def from_arrays(arrays: Mapping[str, np.ndarray], prefix: str = "") -> Any:
    """The value `to_arrays` took apart (KeyError, TypeError or ValueError if they are not such arrays)."""
    return _decode(json.loads(str(arrays[prefix + TREE])), arrays)


def _encode(value: Any, name: str, arrays: dict[str, np.ndarray], patterns: list[tuple[str, sp.csr_matrix]]) -> Any:
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    if isinstance(value, (np.integer, np.floating, np.bool_)):
        return value.item()
    if isinstance(value, np.ndarray):
        arrays[name] = value
        return {"array": name}
    if sp.issparse(value):
        matrix = sp.csr_matrix(value)
        for stored, other in patterns:  # K and M share one pattern: its arrays once
            if other.shape == matrix.shape and np.array_equal(other.indptr, matrix.indptr) \
                    and np.array_equal(other.indices, matrix.indices):
                arrays[name + ".data"] = matrix.data
                return {"csr": name, "pattern": stored, "shape": list(matrix.shape)}
        patterns.append((name, matrix))
        arrays.update({name + ".data": matrix.data, name + ".indices": matrix.indices, name + ".indptr": matrix.indptr})
        return {"csr": name, "pattern": name, "shape": list(matrix.shape)}
    if isinstance(value, (tuple, list)):
        items = [_encode(v, f"{name}.{k}", arrays, patterns) for k, v in enumerate(value)]
        return {"tuple" if isinstance(value, tuple) else "list": items}
    if isinstance(value, Mapping):
        return {"map": [[_encode(k, f"{name}.k{n}", arrays, patterns), _encode(v, f"{name}.v{n}", arrays, patterns)]
                        for n, (k, v) in enumerate(value.items())],
                "frozen": isinstance(value, MappingProxyType)}
    kind = type(value).__name__
    if dataclasses.is_dataclass(value) and CLASSES.get(kind) is type(value):
        return {"dataclass": kind, "fields": {f.name: _encode(getattr(value, f.name), f"{name}.{f.name}", arrays,
                                                              patterns)
                                              for f in dataclasses.fields(value) if f.init}}
    raise TypeError(f"{name or 'value'}: a {kind} cannot be stored as arrays")


def _decode(tree: Any, arrays: Mapping[str, np.ndarray]) -> Any:
    if not isinstance(tree, dict):
        return tree
    if "array" in tree:
        return arrays[tree["array"]]
    if "csr" in tree:
        names = (tree["csr"] + ".data", tree["pattern"] + ".indices", tree["pattern"] + ".indptr")
        shape = tuple(tree["shape"])
        if isinstance(arrays, Entry) and any(arrays.deferred(name) for name in names):
            return DeferredMatrix(lambda: (arrays[names[0]], arrays[names[1]], arrays[names[2]]), shape)
        return sp.csr_matrix((arrays[names[0]], arrays[names[1]], arrays[names[2]]), shape=shape)
    if "tuple" in tree:
        return tuple(_decode(v, arrays) for v in tree["tuple"])
    if "list" in tree:
        return [_decode(v, arrays) for v in tree["list"]]
    if "map" in tree:
        mapping = {_hashable(_decode(k, arrays)): _decode(v, arrays) for k, v in tree["map"]}
        return MappingProxyType(mapping) if tree["frozen"] else mapping
    if "dataclass" in tree:
        cls = CLASSES[tree["dataclass"]]
        return cls(**{name: _decode(v, arrays) for name, v in tree["fields"].items()})
    raise ValueError(f"not a stored value: {sorted(tree)}")


def _hashable(key: Any) -> Any:
    return tuple(key) if isinstance(key, list) else key
