"""The code digest in the cache keys: remembered under the files' sizes, times and inodes, made anew when any
changes, never remembered for files written moments before."""

import os
import time

import pytest

from hitogata import disk_cache
from hitogata.elastic.cache import CODE, SETTLED, package_digest


@pytest.fixture
def package(tmp_path):
    """A small package: two modules and a data file in a subfolder, bytecode beside them, written an hour ago."""
    folder = tmp_path / "package"
    (folder / "data").mkdir(parents=True)
    (folder / "__pycache__").mkdir()
    (folder / "__init__.py").write_text("X = 1\n")
    (folder / "model.py").write_text("def f():\n    return 2\n")
    (folder / "data" / "table.toml").write_text("a = 3\n")
    (folder / "__pycache__" / "model.cpython-311.pyc").write_bytes(b"\0" * 16)
    past = time.time() - 3600
    for path in folder.rglob("*"):
        os.utime(path, (past, past))
    return folder


def remembered(cache_folder) -> int:
    return len(list(cache_folder.glob(f"{CODE}-*.npz")))


def test_remembered_and_read_back(cache_folder, package):
    first = package_digest(package, "1.0")
    assert first.startswith("1.0+") and remembered(cache_folder) == 1
    assert package_digest(package, "1.0") == first
    assert package_digest(package, "1.1") != first  # the version is in the key and the digest
    (package / "__pycache__" / "model.cpython-311.pyc").write_bytes(b"\1" * 16)
    assert package_digest(package, "1.0") == first  # bytecode is no part of it


def test_the_stored_digest_stands_for_the_files_stamps(cache_folder, package, monkeypatch):
    """Rewritten in place to the same size and time (as no editor or checkout leaves a file), the remembered
    digest is what is read: the stamps are what it trusts."""
    first = package_digest(package, "1.0")
    module = package / "model.py"
    stamp = module.stat()
    module.write_text("def f():\n    return 5\n")
    os.utime(module, ns=(stamp.st_atime_ns, stamp.st_mtime_ns))
    assert package_digest(package, "1.0") == first
    monkeypatch.setenv(disk_cache.NO_CACHE_ENV, "1")
    assert package_digest(package, "1.0") != first  # read afresh: the content differs


def test_a_changed_file_makes_a_new_digest(cache_folder, package):
    first = package_digest(package, "1.0")
    table = package / "data" / "table.toml"
    table.write_text("a = 4\n")
    past = time.time() - 60
    os.utime(table, (past, past))
    second = package_digest(package, "1.0")
    assert second != first and remembered(cache_folder) == 2
    (package / "data" / "extra.toml").write_text("b = 1\n")
    os.utime(package / "data" / "extra.toml", (past, past))
    assert package_digest(package, "1.0") not in (first, second)


def test_files_written_just_now_are_not_remembered(cache_folder, package):
    (package / "model.py").write_text("def f():\n    return 6\n")  # now: within SETTLED of the reading
    assert time.time() - (package / "model.py").stat().st_mtime < SETTLED
    package_digest(package, "1.0")
    assert remembered(cache_folder) == 0


def test_the_cache_off_remembers_nothing(cache_folder, package, monkeypatch):
    monkeypatch.setenv(disk_cache.NO_CACHE_ENV, "1")
    package_digest(package, "1.0")
    assert not cache_folder.exists()

