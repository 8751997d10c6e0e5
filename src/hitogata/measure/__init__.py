"""Apparel measurements (ISO 8559-1) and skin strain of a body in any posture.

See docs/measurements.md for every definition, landmark and zone. Pictures,
tables and report files of these figures are the reporting layer's
(`hitogata.report`). The names below are imported on first use (`hitogata.lazy`):
the measurements' names (`values`) come without the measuring.
"""

from typing import TYPE_CHECKING

from hitogata.lazy import lazy_names

if TYPE_CHECKING:
    from hitogata.measure.landmarks import Landmarks, body_landmarks
    from hitogata.measure.measurements import measure, measurement_paths
    from hitogata.measure.strain import SkinStrain, skin_strain
    from hitogata.measure.timeseries import MeasurementSeries, measure_sequence
    from hitogata.measure.values import MEASUREMENT_NAMES, Measurements, undefined_because
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
    "undefined_because",
    "zone_strains",
]
__getattr__, __dir__ = lazy_names(globals(), {
    "Landmarks": "hitogata.measure.landmarks",
    "body_landmarks": "hitogata.measure.landmarks",
    "measure": "hitogata.measure.measurements",
    "measurement_paths": "hitogata.measure.measurements",
    "SkinStrain": "hitogata.measure.strain",
    "skin_strain": "hitogata.measure.strain",
    "MeasurementSeries": "hitogata.measure.timeseries",
    "measure_sequence": "hitogata.measure.timeseries",
    "MEASUREMENT_NAMES": "hitogata.measure.values",
    "Measurements": "hitogata.measure.values",
    "undefined_because": "hitogata.measure.values",
    "ZONE_NAMES": "hitogata.measure.zones",
    "ZoneStrain": "hitogata.measure.zones",
    "body_zones": "hitogata.measure.zones",
    "zone_strains": "hitogata.measure.zones",
})
