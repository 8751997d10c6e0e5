"""The shipped data read through its inflated copy in the disk cache: made once, the same arrays, a damaged
copy never used, nothing written with the cache off."""

import numpy as np
import pytest

from hitogata import disk_cache
from hitogata.body import assets


@pytest.fixture(scope="module")
def shipped() -> dict[str, np.ndarray]:
    """The data file's arrays as the file itself holds them."""
    return assets._inflated(assets.resources.files("hitogata").joinpath("data", assets.DATA_FILE).read_bytes())


def same(arrays: dict[str, np.ndarray], shipped: dict[str, np.ndarray]) -> bool:
    return arrays.keys() == shipped.keys() and all(
        arrays[name].dtype == shipped[name].dtype and np.array_equal(arrays[name], shipped[name]) for name in shipped)


def test_the_first_read_makes_the_copy_the_second_reads_it(cache_folder, shipped):
    assert same(assets._read(assets.DATA_FILE), shipped)
    copies = list(cache_folder.glob(f"{assets.INFLATED}-*.npz"))
    assert len(copies) == 1
    made = copies[0].stat().st_mtime_ns
    assert same(assets._read(assets.DATA_FILE), shipped)
    assert list(cache_folder.glob(f"{assets.INFLATED}-*.npz")) == copies
    shipped_size = len(assets.resources.files("hitogata").joinpath("data", assets.DATA_FILE).read_bytes())
    assert copies[0].stat().st_size > 2 * shipped_size  # stored inflated
    assert copies[0].stat().st_mtime_ns >= made  # read: marked used


def test_a_damaged_copy_is_never_used(cache_folder, shipped, capsys):
    assets._read(assets.DATA_FILE)
    (copy,) = cache_folder.glob(f"{assets.INFLATED}-*.npz")
    data = bytearray(copy.read_bytes())
    middle = len(data) // 2
    data[middle:middle + 64] = bytes(64)  # inside the target offsets: a checksum no longer matches
    copy.write_bytes(bytes(data))
    assert same(assets._read(assets.DATA_FILE), shipped)
    assert "unreadable" in capsys.readouterr().err
    assert same(assets._read(assets.DATA_FILE), shipped)  # from the copy made again
    assert capsys.readouterr().err == ""


def test_the_cache_off_writes_nothing(cache_folder, shipped, monkeypatch):
    monkeypatch.setenv(disk_cache.NO_CACHE_ENV, "1")
    assert same(assets._read(assets.DATA_FILE), shipped)
    assert not cache_folder.exists()
