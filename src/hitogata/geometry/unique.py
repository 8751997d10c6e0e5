"""The distinct rows of an integer array (faces, edges, (vertex, group) pairs): `numpy.unique(..., axis=0)`'s
answers, found on one int64 key a row instead of on the rows as opaque byte strings.

numpy sorts rows with `axis=0` as a structured type, comparing them field by field in a generic sort: on the
tet meshes' faces and star groups it took about 3 % of the test suite's CPU. Rows of non-negative integers
below `base` are the digits of one number in base `base`; where that number fits in 63 bits, its order is
the rows' lexicographic order, so sorting the numbers sorts the rows the same way, and every answer (the rows,
first indices, inverse, counts) is numpy's bit for bit. Other arrays go to numpy as they are.
"""

from __future__ import annotations

from typing import Any

import numpy as np


def unique_rows(rows: np.ndarray, return_index: bool = False, return_inverse: bool = False,
                return_counts: bool = False) -> Any:
    """`numpy.unique(rows, axis=0, ...)` for a 2-D integer array (the inverse always 1-D): the sorted
    distinct rows, and as asked the first index of each, each row's distinct row and each one's count.

    >>> unique_rows(np.array([[2, 1], [0, 5], [2, 1]]), return_inverse=True, return_counts=True)
    (array([[0, 5],
           [2, 1]]), array([1, 0, 1]), array([1, 2]))
    """
    rows = np.asarray(rows)
    keys = _keys(rows)
    if keys is None:
        distinct, first, inverse, counts = np.unique(rows, axis=0, return_index=True, return_inverse=True,
                                                     return_counts=True)
    else:
        _, first, inverse, counts = np.unique(keys, return_index=True, return_inverse=True, return_counts=True)
        distinct = rows[first]
    out: list[np.ndarray] = [distinct]
    if return_index:
        out.append(first)
    if return_inverse:
        out.append(inverse.ravel())
    if return_counts:
        out.append(counts)
    return out[0] if len(out) == 1 else tuple(out)


def _keys(rows: np.ndarray) -> np.ndarray | None:
    """One int64 per row whose order is the rows' lexicographic order, or None where there is none."""
    if rows.ndim != 2 or rows.dtype.kind not in "iu" or rows.shape[1] == 0:
        return None
    if rows.size == 0:
        return np.zeros(len(rows), dtype=np.int64)
    low, high = int(rows.min()), int(rows.max())
    base = high + 1
    if low < 0 or base ** rows.shape[1] >= 2**63:
        return None
    keys = np.zeros(len(rows), dtype=np.int64)
    for column in rows.T:
        keys = keys * base + column.astype(np.int64)
    return keys
