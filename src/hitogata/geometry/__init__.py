"""Geometry utilities over plain vertex/face arrays.

The names below are imported on first use (`hitogata.lazy`): a module needing
vertex normals does not load the self-intersection search and its k-d trees.
"""

from typing import TYPE_CHECKING

from hitogata.lazy import lazy_names

if TYPE_CHECKING:
    from hitogata.geometry.integrity import SurfaceIntegrity, surface_integrity
    from hitogata.geometry.mesh_checks import (
        boundary_edges,
        connected_component_count,
        contains,
        enclosed_volume,
        euler_characteristic,
        genus,
        is_closed,
        is_consistently_oriented,
        self_intersections,
        winding_number,
    )

__all__ = [
    "SurfaceIntegrity",
    "boundary_edges",
    "connected_component_count",
    "contains",
    "enclosed_volume",
    "euler_characteristic",
    "genus",
    "is_closed",
    "is_consistently_oriented",
    "self_intersections",
    "surface_integrity",
    "winding_number",
]
__getattr__, __dir__ = lazy_names(globals(), {
    name: "hitogata.geometry.integrity" if name in ("SurfaceIntegrity", "surface_integrity")
    else "hitogata.geometry.mesh_checks" for name in __all__
})
