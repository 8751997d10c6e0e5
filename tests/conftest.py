"""Shared fixtures (the default bodies are built once per test session) and what each test module needs.

Markers (registered in pyproject.toml), so a machine without a GPU stack,
Chromium or node can deselect what it cannot run: `-m "not render"`,
`-m "not browser"`, `-m "not node"` (the glTF-validator tests mark themselves
through `gltf_validator.needs_validator`), and `-m "not slow"` for a quick run.
"""

import os
import shutil
import tempfile
from pathlib import Path

import pytest

from golden import GoldenFile, golden_path
from hitogata.body import Body, default_body
from hitogata import disk_cache
from hitogata.disk_cache import CACHE_ENV

# Modules whose tests need these, by the module's name.
NEEDS: dict[str, tuple[str, ...]] = {
    # offscreen pictures through pyvista/VTK on Mesa's EGL
    "test_render": ("render",),
    "test_cli_skeleton": ("render",),
    "test_elastic_cli": ("render", "slow"),
    "test_dynamics_outputs": ("render", "slow"),
    "test_garment_dressing": ("render", "slow"),
    # Chromium driven by playwright
    "test_viewer_browser": ("browser", "slow"),
    # an elastic model, a whole-body mesh or a simulation: tens of seconds each
    "test_dynamics_coupling": ("slow",),
    "test_dynamics_large_motion": ("slow",),
    "test_elastic_model": ("slow",),
    "test_elastic_refine": ("slow",),
    "test_fem_dynamics": ("slow",),
    "test_volume_bones": ("slow",),
    "test_volume_model": ("slow",),
    "test_untangle": ("slow",),
    "test_pose_population": ("slow",),
    "test_elastic_ease": ("slow",),  # the whole-body elastic model through a deep squat
    "test_elastic_pose": ("slow",),  # the whole-body elastic model, held
    "test_skin_follows_tissue": ("slow",),  # the demo's and the mobility scenarios' elastic bodies
    "test_carried_surfaces": ("slow",),  # the whole-body elastic model in a short motion
    "test_region_surfaces": ("slow",),  # the whole body's tissue regions on an 8 mm grid
    # a workflow end to end: left out of `make test-fast`, run by `make test`
    "test_readme_examples": ("integration",),
    "test_readme_python": ("integration",),
    "test_tutorial": ("integration",),
    "test_examples": ("integration",),
    "test_study_cluster": ("integration",),
    "test_study_limits": ("integration",),
    "test_viewer_app": ("integration",),
    "test_viewer_player": ("integration",),
    "test_output_writer": ("integration",),
}


_CACHE_FOLDER = pytest.StashKey[str]()
_GOLDEN = pytest.StashKey[dict[Path, GoldenFile]]()


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption("--repin", action="store_true",
                     help="write the figures the tests compute into their golden files (tests/golden.py), in one "
                          "process (-n0), and list those that moved")


def pytest_configure(config: pytest.Config) -> None:
    """The model cache in a folder of this run, never the user's: set before pytest-xdist starts its workers
    (they inherit it and share it), and by each process its own when run alone. `--repin` in one process."""
    if config.getoption("repin") and (config.getoption("numprocesses", None) or 0):
        raise pytest.UsageError("--repin writes the golden files from one process: add -n0")
    config.stash[_GOLDEN] = {}
    if CACHE_ENV not in os.environ or not os.environ.get("PYTEST_XDIST_WORKER"):
        folder = tempfile.mkdtemp(prefix="hitogata-test-cache-")
        os.environ[CACHE_ENV] = folder
        config.stash[_CACHE_FOLDER] = folder


@pytest.fixture(scope="module")
def golden(request: pytest.FixtureRequest) -> GoldenFile:
    """The test module's golden figures (`tests/golden.py`): `golden.check(key, value, rel=..., abs=...)`."""
    files = request.config.stash[_GOLDEN]
    path = golden_path(request.module.__file__)
    if path not in files:
        files[path] = GoldenFile(path, bool(request.config.getoption("repin")))
    return files[path]


def pytest_terminal_summary(terminalreporter, config: pytest.Config) -> None:
    """With --repin: the golden files written, and every figure that moved (old → new)."""
    if not config.getoption("repin"):
        return
    for path, figures in sorted(config.stash.get(_GOLDEN, {}).items()):
        if figures.moved:
            figures.write()
            terminalreporter.write_line(f"{path.relative_to(Path(__file__).parents[1])}: {len(figures.moved)} moved")
            for key, (old, new) in sorted(figures.moved.items()):
                terminalreporter.write_line(f"  {key}: {old} -> {new}")
    if not any(f.moved for f in config.stash.get(_GOLDEN, {}).values()):
        terminalreporter.write_line("golden files: no figure moved")


def pytest_unconfigure(config: pytest.Config) -> None:
    folder = config.stash.get(_CACHE_FOLDER, None)
    if folder is not None:
        shutil.rmtree(folder, ignore_errors=True)


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    for item in items:
        for name in NEEDS.get(item.module.__name__ if item.module else "", ()):
            item.add_marker(getattr(pytest.mark, name))


# `make test` runs the tests on two processes (pytest-xdist, `-n 2 --dist loadscope`): each module on one
# worker, so that a module's fixtures are built once. These modules share more: a default body's whole-body
# elastic model (`elastic_dynamics`, 15-20 s per body, kept on the session's body), so they run on one worker
# together, where it is built once for the female and once for the male.
SHARED_MODEL = ("test_elastic_pose", "test_extreme_poses", "test_self_contact", "test_skin_slide",
                "test_motion_contact", "test_dynamics_large_motion", "test_elastic_ease", "test_carried_surfaces")
# The longest scopes start first, so that no worker is left alone with one at the end (seconds in one process,
# measured: each case of the validation envelope 170-330 s, the identification 110 s, the shared model's modules 220 s, test_body_mesh_grid 190 s, test_skin_follows_tissue 160 s,
# test_fit_scan 80 s, test_extreme_bodies 65 s, test_made_to_measure 50 s, then 40 s or less each); the others
# as pytest-xdist orders them.
SHARED_MODEL_SCOPE = "shared whole-body model"
LONGEST = ("test_validation_envelope[female]", "test_validation_identify", "test_validation_envelope[male]",
           SHARED_MODEL_SCOPE, "test_body_mesh_grid", "test_skin_follows_tissue", "test_fit_scan",
           "test_garment_dressing",
           "test_extreme_bodies", "test_made_to_measure", "test_study_cluster", "test_viewer_browser",
           "test_dynamics_coupling",
           "test_readme_examples", "test_elastic_model")


# Modules whose parametrised cases are work units of their own (each case minutes long, nothing shared
# between them but the session's bodies), so that the two workers take them side by side.
BY_CASE = ("test_validation_envelope",)


def _scope(nodeid: str) -> str:
    """The work unit a test belongs to: its module, the modules sharing a whole-body model, or one case."""
    path = nodeid.split("::", 1)[0]
    module = path.rsplit("/", 1)[-1].removesuffix(".py")
    if module in BY_CASE and "[" in nodeid:
        return module + nodeid[nodeid.index("["):]
    return SHARED_MODEL_SCOPE if module in SHARED_MODEL else module


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config: pytest.Config, log):
    """`--dist loadscope` with the scopes above; any other `--dist` as pytest-xdist has it."""
    if config.getoption("dist") != "loadscope":
        return None
    from xdist.scheduler import LoadScopeScheduling

    class SharedScopes(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            return _scope(nodeid)

        def _assign_work_unit(self, node) -> None:
            first = min(self.workqueue, key=lambda s: LONGEST.index(s) if s in LONGEST else len(LONGEST))
            self.workqueue.move_to_end(first, last=False)
            super()._assign_work_unit(node)

    return SharedScopes(config, log)


@pytest.fixture(scope="session")
def female() -> Body:
    return default_body("female")


@pytest.fixture(scope="session")
def male() -> Body:
    return default_body("male")


@pytest.fixture
def cache_folder(tmp_path, monkeypatch) -> Path:
    """A disk cache of the test's own, on, at the default size limit."""
    folder = tmp_path / "cache"
    monkeypatch.setenv(CACHE_ENV, str(folder))
    monkeypatch.delenv(disk_cache.NO_CACHE_ENV, raising=False)
    monkeypatch.delenv(disk_cache.LIMIT_ENV, raising=False)
    return folder


@pytest.fixture(scope="module")
def client():
    """A dask.distributed LocalCluster of 2 worker processes and its client, per test module."""
    import dask

    from hitogata.study.runner import local_cluster

    # Generous connection timeouts: the machine is shared and a worker may take long to start.
    with dask.config.set({"distributed.comm.timeouts.connect": "300s", "distributed.comm.timeouts.tcp": "300s"}):
        cluster, client = local_cluster(2, "2GiB", dashboard=None)
        try:
            yield client
        finally:
            client.close()
            cluster.close()
