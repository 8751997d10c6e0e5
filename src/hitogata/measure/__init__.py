"""Apparel measurements (ISO 8559-1) and skin strain of a body in any posture.

See docs/measurements.md for every definition, landmark and zone.
"""

from hitogata.measure.cli_support import measure_report, measurement_table
from hitogata.measure.landmarks import Landmarks, body_landmarks
from hitogata.measure.measurements import MEASUREMENT_NAMES, Measurements, measure, measurement_paths
from hitogata.measure.rig_joints import posed_rig_heads
from hitogata.measure.strain import SkinStrain, skin_strain
from hitogata.measure.timeseries import MeasurementSeries, measure_sequence, series_csv, series_plot, write_series
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
    "measure_report",
    "measure_sequence",
    "measurement_paths",
    "measurement_table",
    "posed_rig_heads",
    "series_csv",
    "series_plot",
    "skin_strain",
    "write_series",
    "zone_strains",
]
