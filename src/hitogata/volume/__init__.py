"""Volumetric body model: tetrahedral meshes of the trunk or the whole body with tissue regions.

`build_trunk_model(body)` is the paper's trunk; `build_body_model(body)` the
whole body. The mesher (`lattice.stuff`) and its queries work on plain arrays.
"""

from hitogata.volume.anatomy import MUSCLES, REGIONS
from hitogata.volume.lattice import TetMesh, stuff
from hitogata.volume.model import (
    DEFAULT_ELEMENT_SIZE,
    VolumeModel,
    VolumeQuality,
    build_body_model,
    build_trunk_model,
    build_volume_model,
)

__all__ = [
    "DEFAULT_ELEMENT_SIZE",
    "MUSCLES",
    "REGIONS",
    "TetMesh",
    "VolumeModel",
    "VolumeQuality",
    "build_body_model",
    "build_trunk_model",
    "build_volume_model",
    "stuff",
]
