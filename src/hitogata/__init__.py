"""hitogata: a physically based, posable human body model for apparel design.

The whole pipeline from one import (SI units: metres, kilograms, radians)::

    import hitogata as hg

    body = hg.Body.from_measurements(sex="female", age=30, stature=1.65, mass=58.0)
    posed = hg.pose_body(body, contractions={"biceps_brachii_l": 0.25})   # 25 % shorter
    hg.measure(posed).waist_girth                                        # m
    model = hg.build_elastic_model(body)                                 # trunk, P2, 40 modes
    motion = hg.simulate(hg.BodyDynamics.build(body, model), timeline, duration=1.0, rate=30)

Each name is imported on first use, so `import hitogata` stays cheap; the
subpackages (`hitogata.body`, `.posing`, `.elastic`, `.dynamics`, `.skin`,
`.measure`, `.export`, ...) hold the rest.
"""

from __future__ import annotations

import sys
from importlib import import_module
from types import ModuleType
from typing import TYPE_CHECKING, Any

# name -> the module that defines it
_EXPORTS: dict[str, str] = {
    # the body
    "Body": "hitogata.body.model",
    "default_body": "hitogata.body.model",
    "body_to_measure": "hitogata.made_to_measure.solve",
    "ShapeParameters": "hitogata.body.shape",
    # posing by muscles and joint angles
    "Poser": "hitogata.posing.pose",
    "PosedBody": "hitogata.posing.pose",
    "pose_body": "hitogata.posing.pose",
    "poser_for": "hitogata.posing.pose",
    # the elastic (finite-element) model
    "ElasticModel": "hitogata.elastic.model",
    "build_elastic_model": "hitogata.elastic.model",
    "Materials": "hitogata.elastic.materials",
    "load_materials": "hitogata.elastic.materials",
    # dynamics and scenarios
    "BodyDynamics": "hitogata.dynamics.motion",
    "Motion": "hitogata.dynamics.motion",
    "simulate": "hitogata.skin.motion_contact",
    "Keyframe": "hitogata.dynamics.timeline",
    "Timeline": "hitogata.dynamics.timeline",
    "Scenario": "hitogata.motion.scenario",
    "load_scenario": "hitogata.motion.scenario",
    "shipped_scenarios": "hitogata.motion.scenario",
    "run_scenario": "hitogata.simulation.run",
    # measurement
    "Measurements": "hitogata.measure.values",
    "measure": "hitogata.measure.measurements",
    "SkinStrain": "hitogata.measure.strain",
    "skin_strain": "hitogata.measure.strain",
    "zone_strains": "hitogata.measure.zones",
    # files
    "write_body": "hitogata.export.body_files",
    "write_posed": "hitogata.export.pose_files",
    "write_mesh": "hitogata.export.meshfiles",
    "write_motion_glb": "hitogata.export.motion_files",
    "write_pvd": "hitogata.export.motion_files",
    "write_sequence": "hitogata.export.motion_files",
    # beside measured people
    "load_dataset": "hitogata.validation.dataset",
    "answer_dataset": "hitogata.validation.answers",
    "compare": "hitogata.validation.table",
    "identify": "hitogata.validation.identify",
    # errors
    "HitogataError": "hitogata.errors",
}

# Spelled out for linters and type checkers; tests/api/test_front_door.py checks it matches _EXPORTS.
__all__ = [
    "__version__",
    "answer_dataset",
    "Body",
    "BodyDynamics",
    "body_to_measure",
    "build_elastic_model",
    "compare",
    "default_body",
    "ElasticModel",
    "HitogataError",
    "identify",
    "Keyframe",
    "load_dataset",
    "load_materials",
    "load_scenario",
    "Materials",
    "measure",
    "Measurements",
    "Motion",
    "pose_body",
    "PosedBody",
    "Poser",
    "poser_for",
    "run_scenario",
    "Scenario",
    "ShapeParameters",
    "shipped_scenarios",
    "simulate",
    "skin_strain",
    "SkinStrain",
    "Timeline",
    "write_body",
    "write_mesh",
    "write_motion_glb",
    "write_posed",
    "write_pvd",
    "write_sequence",
    "zone_strains",
]

if TYPE_CHECKING:
    from hitogata.body.model import Body, default_body
    from hitogata.export.motion_files import write_motion_glb, write_pvd, write_sequence
    from hitogata.dynamics.motion import BodyDynamics, Motion
    from hitogata.skin.motion_contact import simulate
    from hitogata.simulation.run import run_scenario
    from hitogata.motion.scenario import Scenario, load_scenario, shipped_scenarios
    from hitogata.dynamics.timeline import Keyframe, Timeline
    from hitogata.elastic.materials import Materials, load_materials
    from hitogata.elastic.model import ElasticModel, build_elastic_model
    from hitogata.errors import HitogataError
    from hitogata.export.body_files import write_body
    from hitogata.export.meshfiles import write_mesh
    from hitogata.export.pose_files import write_posed
    from hitogata.made_to_measure.solve import body_to_measure
    from hitogata.measure.measurements import measure
    from hitogata.measure.values import Measurements
    from hitogata.validation.answers import answer_dataset
    from hitogata.validation.dataset import load_dataset
    from hitogata.validation.identify import identify
    from hitogata.validation.table import compare
    from hitogata.measure.strain import SkinStrain, skin_strain
    from hitogata.measure.zones import zone_strains
    from hitogata.posing.pose import PosedBody, Poser, pose_body, poser_for
    from hitogata.body.shape import ShapeParameters

    __version__: str


def __getattr__(name: str) -> Any:
    """Import an exported name's module on first use (PEP 562) and keep the name here."""
    if name == "__version__":
        from importlib.metadata import PackageNotFoundError, version

        try:
            value: Any = version("hitogata")
        except PackageNotFoundError:  # run from a source tree that was never installed
            value = "0+unknown"
    elif name in _EXPORTS:
        value = getattr(import_module(_EXPORTS[name]), name)
    else:
        raise AttributeError(f"module 'hitogata' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted([*globals(), *_EXPORTS, "__version__"])


class _FrontDoor(ModuleType):
    """This package, keeping `hitogata.measure` the function once the `hitogata.measure` subpackage
    is imported (the import system would otherwise bind the subpackage over it)."""

    def __setattr__(self, name: str, value: Any) -> None:
        if name in _EXPORTS and isinstance(value, ModuleType):
            return
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _FrontDoor
