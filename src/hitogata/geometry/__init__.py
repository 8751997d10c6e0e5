"""Geometry utilities over plain vertex/face arrays."""

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
