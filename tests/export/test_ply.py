"""The PLY writer: the body's skin read back the same by trimesh and by meshio, its data as trimesh writes it."""

from pathlib import Path

import meshio
import numpy as np
import pytest
import trimesh

from hitogata.body.assets import load_assets, skin_points
from hitogata.export import write_mesh


@pytest.fixture(scope="module")
def skin() -> tuple[np.ndarray, np.ndarray]:
    """The MakeHuman base skin: 13 k vertices, 24 k triangles."""
    assets = load_assets()
    return skin_points(assets, assets.base_vertices), assets.triangles


@pytest.fixture(scope="module")
def written(skin, tmp_path_factory) -> Path:
    return write_mesh(tmp_path_factory.mktemp("ply") / "skin.ply", *skin)


def test_trimesh_reads_the_same_mesh(written, skin):
    vertices, faces = skin
    back = trimesh.load(written, process=False)
    assert np.array_equal(back.vertices, vertices.astype(np.float32))  # float32: the file's precision
    assert np.abs(back.vertices - vertices).max() < 1e-6  # metres, for a body within 2 m of its origin
    assert np.array_equal(back.faces, faces)


def test_meshio_reads_the_same_mesh(written, skin):
    vertices, faces = skin
    back = meshio.read(written)
    assert np.array_equal(back.points, vertices.astype(np.float32))
    assert [block.type for block in back.cells] == ["triangle"]
    assert np.array_equal(back.cells[0].data, faces)


def test_data_as_trimesh_writes_it(written, skin):
    ours = written.read_bytes()
    theirs = trimesh.Trimesh(*skin, process=False).export(file_type="ply")
    end = b"end_header\n"
    assert ours[ours.index(end) + len(end):] == theirs[theirs.index(end) + len(end):]
    assert ours[:ours.index(end)].replace(b"comment hitogata\n", b"") == \
        theirs[:theirs.index(end)].replace(b"comment https://github.com/mikedh/trimesh\n", b"")
