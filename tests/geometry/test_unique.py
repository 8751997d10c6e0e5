"""`geometry.unique.unique_rows` gives `numpy.unique(axis=0)`'s answers on the meshes' integer rows."""

from __future__ import annotations

import numpy as np
import pytest

from hitogata.body import default_body
from hitogata.geometry.unique import unique_rows


def numpy_answers(rows: np.ndarray) -> tuple[np.ndarray, ...]:
    found = np.unique(rows, axis=0, return_index=True, return_inverse=True, return_counts=True)
    return found[0], found[1], found[2].ravel(), found[3]


@pytest.mark.parametrize("rows", [
    np.random.default_rng(1).integers(0, 50, size=(4000, 3)),  # many repeated rows
    np.random.default_rng(2).integers(0, 2**20, size=(3000, 3)),  # wide values, a 60-bit key
    np.random.default_rng(3).integers(-3, 3, size=(500, 2)),  # negative: numpy's own path
    np.random.default_rng(4).integers(0, 2**40, size=(200, 2)),  # no 63-bit key: numpy's own path
    np.zeros((0, 3), dtype=np.int64),
])
def test_the_answers_are_numpys(rows):
    ours = unique_rows(rows, return_index=True, return_inverse=True, return_counts=True)
    for mine, theirs in zip(ours, numpy_answers(rows)):
        assert mine.dtype == theirs.dtype and np.array_equal(mine, theirs)
    assert np.array_equal(unique_rows(rows), np.unique(rows, axis=0))


def test_the_body_edges_each_held_by_two_triangles():
    faces = default_body("female").faces
    edges = np.sort(faces[:, [[0, 1], [1, 2], [2, 0]]].reshape(-1, 2), axis=1)
    unique, inverse, counts = unique_rows(edges, return_inverse=True, return_counts=True)
    assert np.array_equal(unique[inverse], edges)
    assert len(unique) == len(faces) * 3 // 2 and (counts == 2).all()  # a closed surface
