"""Computation never imports plotting, rendering or file-format code; `import hitogata` loads nothing else.

Each import runs in a fresh interpreter, so what another test imported cannot hide a leak.
"""

import subprocess
import sys

import pytest

COMPUTATION = ["body", "body.model", "body.shape", "body.rig", "body.rest_contact", "skeleton", "muscles", "posing",
               "posing.pose", "posing.skinning", "volume", "fem", "elastic", "dynamics", "skin", "skin.single_pose",
               "skin.motion_contact", "measure", "geometry",
               "options", "units", "made_to_measure", "made_to_measure.solve",
               "made_to_measure.measurement_rates", "made_to_measure.size_chart", "made_to_measure.scan_fit"]
PRESENTATION = ("matplotlib", "pyvista", "vtk", "vtkmodules", "meshio", "pygltflib", "viser", "trimesh", "PIL", "tqdm")


def loaded_after(statement: str) -> set[str]:
    code = f"import sys\n{statement}\nprint(' '.join(sorted(sys.modules)))"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return set(result.stdout.split())


@pytest.mark.parametrize("package", COMPUTATION)
def test_computation_imports_no_presentation_or_file_format_library(package: str) -> None:
    loaded = loaded_after(f"import hitogata.{package}")
    leaked = sorted(name for name in PRESENTATION if name in loaded)
    assert not leaked, f"import hitogata.{package} loads {', '.join(leaked)}"
    assert not any(m.startswith(("hitogata.report", "hitogata.render", "hitogata.export", "hitogata.viewer",
                                 "hitogata.commands")) for m in loaded), package


def test_import_hitogata_loads_only_itself() -> None:
    loaded = loaded_after("import hitogata")
    assert sorted(m for m in loaded if m.startswith("hitogata")) == ["hitogata"]
    assert "numpy" not in loaded


@pytest.mark.parametrize("package", ["body", "export", "geometry", "made_to_measure", "made_to_measure.scan_fit",
                                     "measure", "motion", "posing", "simulation", "skin", "volume"])
def test_a_package_importing_its_names_on_first_use_resolves_each(package: str) -> None:
    """`hitogata.lazy`: every name in the package's __all__ is its defining module's, and listed by dir()."""
    import importlib

    module = importlib.import_module(f"hitogata.{package}")
    for name in module.__all__:
        value = getattr(module, name)
        defining = getattr(value, "__module__", None)
        assert defining is None or defining.startswith(f"hitogata.{package}."), (name, defining)
        assert name in dir(module)
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        module.nothing  # noqa: B018


def test_measuring_a_body_file_loads_no_plotting_nor_writers_libraries() -> None:
    """`hitogata measure body.glb` (the command's module and its report): the picture is drawn without
    matplotlib, the GLB read without pygltflib, and neither the mesher nor the dynamics are loaded."""
    loaded = loaded_after("import hitogata.commands.measure, hitogata.report.measurements")
    assert not {"matplotlib", "pygltflib", "trimesh", "meshio", "pyvista"} & loaded
    assert not {"hitogata.volume.lattice", "hitogata.dynamics", "hitogata.made_to_measure.scan_fit.scanfit"} & loaded
