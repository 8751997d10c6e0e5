"""Shared fixtures (the default bodies are built once per test session) and what each test module needs.

Markers (registered in pyproject.toml), so a machine without a GPU stack,
Chromium or node can deselect what it cannot run: `-m "not render"`,
`-m "not browser"`, `-m "not node"` (the glTF-validator tests mark themselves
through `gltf_validator.needs_validator`), and `-m "not slow"` for a quick run.
"""

import pytest

from hitogata.body import Body, default_body

# Modules whose tests need these, by the module's name.
NEEDS: dict[str, tuple[str, ...]] = {
    # offscreen pictures through pyvista/VTK on Mesa's EGL
    "test_render": ("render",),
    "test_cli_skeleton": ("render",),
    "test_elastic_cli": ("render", "slow"),
    "test_dynamics_outputs": ("render", "slow"),
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
}


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    for item in items:
        for name in NEEDS.get(item.module.__name__ if item.module else "", ()):
            item.add_marker(getattr(pytest.mark, name))


@pytest.fixture(scope="session")
def female() -> Body:
    return default_body("female")


@pytest.fixture(scope="session")
def male() -> Body:
    return default_body("male")
