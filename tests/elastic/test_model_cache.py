"""The disk cache of elastic models: keyed by all it is built from, shared safely, never read corrupt."""

import os
import pickle
import subprocess
from concurrent.futures import ThreadPoolExecutor
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

from hitogata import disk_cache
from hitogata.body import Body
from hitogata.cli import main
from hitogata.dynamics.model_cache import cached_dynamics
from hitogata.skin.single_pose import elastic_pose
from hitogata.elastic import load_materials
from hitogata.disk_cache import cached
from hitogata.elastic.cache import model_key, model_options
from hitogata.elastic.stored import DeferredMatrix, from_arrays, to_arrays
from hitogata.errors import HitogataError
from hitogata.fem import Material


def _softer_muscle(materials):
    """The same materials file, its muscle's modulus 10 % lower: the same name, other values."""
    muscle = materials.regions["muscle"]
    regions = {**materials.regions, "muscle": Material(muscle.E * 0.9, muscle.nu, muscle.rho, "muscle")}
    return replace(materials, regions=regions)


def test_a_changed_material_element_size_or_body_misses_the_cache(female):
    table = load_materials()
    base = model_key(female, model_options(extent="body", element_size=40.0, n_modes=2, materials=table))
    assert base == model_key(female, model_options(extent="body", element_size=40.0, n_modes=2,
                                                   materials=load_materials()))
    softer = _softer_muscle(table)
    assert softer.source == table.source
    other = Body.from_measurements("female", 30.0, 1.70, 62.0)
    for changed in (model_key(female, model_options(extent="body", element_size=40.0, n_modes=2, materials=softer)),
                    model_key(female, model_options(extent="body", element_size=35.0, n_modes=2, materials=table)),
                    model_key(female, model_options(extent="body", element_size=40.0, n_modes=4, materials=table)),
                    model_key(other, model_options(extent="body", element_size=40.0, n_modes=2, materials=table))):
        assert changed != base
        assert disk_cache.entry_path("dynamics", changed) != disk_cache.entry_path("dynamics", base)


def test_a_stored_entry_is_read_back_and_a_miss_builds(cache_folder):
    built = []

    def build():
        built.append(1)
        return np.arange(5.0)

    def fetch(key):
        return cached("test", key, build, lambda v: {"v": v}, lambda a: a["v"], None)

    np.testing.assert_array_equal(fetch({"n": 1}), np.arange(5.0))
    np.testing.assert_array_equal(fetch({"n": 1}), np.arange(5.0))
    assert len(built) == 1
    fetch({"n": 2})
    assert len(built) == 2
    assert cached("test", {"n": 1}, build, lambda v: {"v": v}, lambda a: a["v"], False) is not None
    assert len(built) == 3  # cache=False: built, not read


def test_a_corrupt_entry_is_rebuilt_with_a_note(cache_folder, capsys):
    key = {"n": 1}
    disk_cache.save("test", key, {"v": np.arange(100_000.0)})
    path = disk_cache.entry_path("test", key)
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])  # cut short, as a full disk or a killed writer would leave it
    rebuilt = cached("test", key, lambda: np.zeros(3), lambda v: {"v": v}, lambda a: a["v"], None)
    np.testing.assert_array_equal(rebuilt, np.zeros(3))  # the half entry never used
    notes = [line for line in capsys.readouterr().err.splitlines() if line]
    assert len(notes) == 1 and notes[0].startswith("hitogata: note: cache entry") and path.name in notes[0]
    np.testing.assert_array_equal(disk_cache.load("test", key)["v"], np.zeros(3))  # and stored whole again

    flipped = bytearray(path.read_bytes())
    flipped[len(flipped) // 2] ^= 0xFF  # a damaged byte inside an array: the zip's checksum catches it
    path.write_bytes(bytes(flipped))
    assert disk_cache.load("test", key) is None
    assert "hitogata: note: cache entry" in capsys.readouterr().err
    assert not path.exists()


def _stiff(n: int) -> sp.csr_matrix:
    """A sparse symmetric matrix of n rows, a stand-in for K."""
    return sp.csr_matrix(sp.diags([np.full(n - 1, -1.0), np.full(n, 2.5), np.full(n - 1, -1.0)], [-1, 0, 1]))


def test_deferred_members_are_read_when_first_used_from_the_file_as_opened(cache_folder):
    """A held posture does not read K and M: an entry's deferred members are read when first used, from the
    entry as it was opened, even if another process has since renamed a new entry into its place."""
    key, K = {"n": 1}, _stiff(50_000)
    disk_cache.save("test", key, to_arrays((np.arange(3.0), K)))
    entry = disk_cache.load("test", key, deferred=lambda name: name.startswith(".1."))
    value = from_arrays(entry)
    assert all(entry.deferred(name) for name in (".1.data", ".1.indices", ".1.indptr"))
    np.testing.assert_array_equal(value[0], np.arange(3.0))
    matrix = value[1]
    assert isinstance(matrix, DeferredMatrix) and not matrix.arrays_read and entry.deferred(".1.data")
    disk_cache.save("test", key, to_arrays((np.zeros(3), 2.0 * K)))  # another writer's entry, renamed in
    x = np.linspace(0.0, 1.0, K.shape[0])
    np.testing.assert_array_equal(matrix @ x, K @ x)  # the first use reads this entry's K, not the new one's
    assert matrix.arrays_read and not entry.deferred(".1.data")
    assert (matrix != K).nnz == 0 and matrix.shape == K.shape
    assert abs((matrix - 0.5 * matrix) - 0.5 * K).max() == 0.0  # scipy's products of it are matrices like any
    plain = pickle.loads(pickle.dumps(matrix))  # to a Dask worker: a plain CSR matrix
    assert type(plain) is sp.csr_matrix and (plain != K).nnz == 0


def test_threads_first_using_deferred_matrices_at_once_each_get_the_matrix(cache_folder):
    """K and M share their pattern's arrays: threads first using both at once read each member once, whole."""
    key, K = {"n": 3}, _stiff(50_000)
    disk_cache.save("test", key, to_arrays((K, 2.0 * K)))
    entry = disk_cache.load("test", key, deferred=lambda name: True)
    stiffness, mass = from_arrays(entry)
    x = np.linspace(0.0, 1.0, K.shape[0])
    with ThreadPoolExecutor(4) as pool:
        products = list(pool.map(lambda m: m @ x, [stiffness, mass, stiffness, mass]))
    for product, factor in zip(products, (1.0, 2.0, 1.0, 2.0)):
        np.testing.assert_array_equal(product, factor * (K @ x))


def test_a_damaged_deferred_member_is_never_used(cache_folder, capsys):
    key = {"n": 2}
    disk_cache.save("test", key, to_arrays((np.arange(3.0), _stiff(50_000))))
    path = disk_cache.entry_path("test", key)
    data = bytearray(path.read_bytes())
    at = data.find(np.array([-1.0, 2.5, -1.0] * 2).tobytes())  # inside the matrix's data
    assert at > 0
    data[at + 3] ^= 0xFF
    path.write_bytes(bytes(data))
    entry = disk_cache.load("test", key, deferred=lambda name: name.startswith(".1."))
    assert entry is not None  # the members read at once are whole
    matrix = from_arrays(entry)[1]
    with pytest.raises(HitogataError, match="damaged"):
        matrix @ np.ones(matrix.shape[1])
    notes = [line for line in capsys.readouterr().err.splitlines() if line]
    assert len(notes) == 1 and notes[0].startswith("hitogata: note: cache entry") and path.name in notes[0]
    assert not path.exists()  # removed: the next run builds it again


WRITER = """
import sys, time
from pathlib import Path
import numpy as np
from hitogata import disk_cache
go = Path(sys.argv[1])
while not go.exists():
    time.sleep(0.01)
value = np.full(4_000_000, float(sys.argv[2]))
for _ in range(3):
    disk_cache.save("test", {"shared": 1}, {"v": value})
"""


def test_two_processes_writing_one_entry_end_with_one_valid_entry(cache_folder, tmp_path):
    go = tmp_path / "go"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(Path(disk_cache.__file__).parents[1]),
                                                        os.environ.get("PYTHONPATH", "")])}
    writers = [subprocess.Popen([sys.executable, "-c", WRITER, str(go), str(k)], env=env) for k in (1, 2)]
    go.touch()  # both start together
    assert [w.wait() for w in writers] == [0, 0]
    assert [p.name for p in cache_folder.iterdir()] == [disk_cache.entry_path("test", {"shared": 1}).name]
    value = disk_cache.load("test", {"shared": 1})["v"]
    assert len(value) == 4_000_000 and value[0] in (1.0, 2.0) and np.all(value == value[0])


ASKER = """
import sys, time
from pathlib import Path
import numpy as np
from hitogata.disk_cache import cached
folder, me = Path(sys.argv[1]), sys.argv[2]
def build():
    with open(folder / "builds", "a") as log:
        log.write(me + "\\n")
    while len(list(folder.glob("asked-*"))) < 2:  # the other process has asked too: it waits on this build
        time.sleep(0.01)
    return np.full(1000, float(me))
(folder / f"asked-{me}").touch()
value = cached("test", {"asked": 1}, build, lambda v: {"v": v}, lambda a: a["v"], None)
print(value[0])
"""


def test_two_processes_asking_for_one_entry_build_it_once(cache_folder, tmp_path):
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(Path(disk_cache.__file__).parents[1]),
                                                        os.environ.get("PYTHONPATH", "")])}
    askers = [subprocess.Popen([sys.executable, "-c", ASKER, str(tmp_path), str(k)], env=env, stdout=subprocess.PIPE,
                               text=True) for k in (1, 2)]
    answers = [float(asker.communicate()[0]) for asker in askers]
    assert [asker.returncode for asker in askers] == [0, 0]
    builders = (tmp_path / "builds").read_text().split()
    assert len(builders) == 1  # the second waited for the first's build and read it
    assert answers == [float(builders[0])] * 2


def test_the_cache_keeps_within_its_limit(cache_folder, monkeypatch):
    monkeypatch.setenv(disk_cache.LIMIT_ENV, "2")  # MB: room for two of these entries
    for n in range(4):
        disk_cache.save("test", {"n": n}, {"v": np.zeros(100_000)})  # 0.8 MB each
        os.utime(disk_cache.entry_path("test", {"n": n}), (n, n))  # used in this order
    assert disk_cache.load("test", {"n": 3}) is not None  # the newest stays
    assert disk_cache.load("test", {"n": 0}) is None  # the oldest went
    assert disk_cache.info().size <= 2e6


def test_cache_command_tells_and_clears(cache_folder, capsys):
    disk_cache.save("test", {"n": 1}, {"v": np.zeros(1000)})
    assert main(["cache", "--info"]) == 0
    assert f"{cache_folder}: 1 entries" in capsys.readouterr().out
    assert main(["cache", "--clear"]) == 0
    assert "removed 1 entries" in capsys.readouterr().out
    assert disk_cache.info().entries == 0


@pytest.mark.slow
def test_the_cached_model_poses_the_same_skin_as_a_fresh_build(female, cache_folder):
    """One build, stored; the second call reads it back: the same skin to round-off at held postures."""
    options = {"extent": "body", "element_size": 40.0, "n_modes": 2}
    fresh = cached_dynamics(female, **options)
    assert len(list(cache_folder.glob("dynamics-*.npz"))) == 1
    stored = cached_dynamics(female, **options)
    assert stored is not fresh
    for clinical, contact in (({"shank_r.flexion": np.radians(135)}, True), ({"forearm_l.flexion": np.radians(120)},
                                                                            False)):
        a = elastic_pose(fresh, clinical=clinical, contact=contact)
        b = elastic_pose(stored, clinical=clinical, contact=contact)
        assert np.abs(a.vertices - b.vertices).max() < 1e-9


def test_no_cache_on_a_command_turns_the_cache_off_for_its_run(cache_folder, monkeypatch, capsys):
    monkeypatch.setenv(disk_cache.NO_CACHE_ENV, "0")  # restored after the test
    assert disk_cache.enabled()
    assert main(["pose", "--no-cache", "--list"]) == 0
    assert not disk_cache.enabled()  # and the processes it starts inherit it
    assert "muscles" in capsys.readouterr().out
