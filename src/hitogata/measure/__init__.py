"""Apparel measurements (ISO 8559-1) and skin strain of a body in any posture.

See docs/measurements.md for every definition, landmark and zone. Pictures,
tables and report files of these figures are the reporting layer's
(`hitogata.report`).
"""

from hitogata.measure.landmarks import Landmarks, body_landmarks
from hitogata.measure.measurements import MEASUREMENT_NAMES, Measurements, measure, measurement_paths
from hitogata.measure.strain import SkinStrain, skin_strain
from hitogata.measure.timeseries import MeasurementSeries, measure_sequence
from hitogata.measure.zones import ZONE_NAMES, ZoneStrain, body_zones, zone_strains

__all__ = [
    "MEASUREMENT_NAMES",
    "ZONE_NAMES",
    "Landmarks",
    "MeasurementSeries",
    "Measurements",
    "SkinStrain",
    "ZoneStrain",
    "body_landmarks",
    "body_zones",
    "measure",
    "measure_sequence",
    "measurement_paths",
    "skin_strain",
    "zone_strains",
]
