"""What a garment meets on the body: fabric tension, interface pressure, dynamic ease (docs/garment.md)."""

from hitogata.garment.fabric import Fabric, read_fabric_csv
from hitogata.garment.pressure import (
    COMPRESSION_CLASSES,
    Garment,
    LevelPressure,
    compression_class,
    garment_pressure,
    laplace_profile,
)

__all__ = [
    "COMPRESSION_CLASSES",
    "Fabric",
    "Garment",
    "LevelPressure",
    "compression_class",
    "garment_pressure",
    "laplace_profile",
    "read_fabric_csv",
]
