"""Made to measure: a body of the asked measurements, above `hitogata.measure`, whose measurements
it asks the body to meet.

- `solve`: `body_to_measure`, the shape that has the asked tape measurements (bounded least squares
  on `measure`'s own values), with its report of asked against made (`MadeToMeasure`);
- `measurement_rates`: how fast each measurement changes as the skin moves (the solve's Jacobian);
- `size_chart`: a size chart read and checked, one request per size;
- `scan_fit`: a body from a scan, the body model registered to a mesh or point cloud.

`Body.from_measurements(..., chest=...)` hands the measurements other than stature and mass to
`body_to_measure`. The names below are imported on first use (`hitogata.lazy`).
"""

from typing import TYPE_CHECKING

from hitogata.lazy import lazy_names

if TYPE_CHECKING:
    from hitogata.made_to_measure.size_chart import read_size_chart, shipped_size_charts
    from hitogata.made_to_measure.solve import MadeToMeasure, MeasurementWarning, body_to_measure

__all__ = ["MadeToMeasure", "MeasurementWarning", "body_to_measure", "read_size_chart", "shipped_size_charts"]
__getattr__, __dir__ = lazy_names(globals(), {
    "MadeToMeasure": "hitogata.made_to_measure.solve",
    "MeasurementWarning": "hitogata.made_to_measure.solve",
    "body_to_measure": "hitogata.made_to_measure.solve",
    "read_size_chart": "hitogata.made_to_measure.size_chart",
    "shipped_size_charts": "hitogata.made_to_measure.size_chart",
})
