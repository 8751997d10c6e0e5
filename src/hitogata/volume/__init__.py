"""Volumetric body model: tetrahedral meshes of the trunk or the whole body with tissue regions.

`build_trunk_model(body)` is the paper's trunk; `build_body_model(body)` the
whole body. The mesher (`lattice.stuff`) and its queries work on plain arrays;
`repair` makes the whole body's stuffed mesh whole and `mesh_integrity` says
whether a mesh is (pieces, pinches, manifold boundary, hold, angles). The names
below are imported on first use (`hitogata.lazy`): a surface query (`surface`)
does not load the mesher.
"""

from typing import TYPE_CHECKING

from hitogata.lazy import lazy_names

if TYPE_CHECKING:
    from hitogata.volume.anatomy import MUSCLES, REGIONS
    from hitogata.volume.integrity import MeshIntegrity, mesh_integrity
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
    "MeshIntegrity",
    "MUSCLES",
    "REGIONS",
    "TetMesh",
    "VolumeModel",
    "VolumeQuality",
    "build_body_model",
    "build_trunk_model",
    "build_volume_model",
    "mesh_integrity",
    "stuff",
]
__getattr__, __dir__ = lazy_names(globals(), {
    "MUSCLES": "hitogata.volume.anatomy",
    "REGIONS": "hitogata.volume.anatomy",
    "MeshIntegrity": "hitogata.volume.integrity",
    "mesh_integrity": "hitogata.volume.integrity",
    "TetMesh": "hitogata.volume.lattice",
    "stuff": "hitogata.volume.lattice",
    "DEFAULT_ELEMENT_SIZE": "hitogata.volume.model",
    "VolumeModel": "hitogata.volume.model",
    "VolumeQuality": "hitogata.volume.model",
    "build_body_model": "hitogata.volume.model",
    "build_trunk_model": "hitogata.volume.model",
    "build_volume_model": "hitogata.volume.model",
})
