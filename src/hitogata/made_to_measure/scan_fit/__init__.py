"""A body from a scan: register the body model to a triangle mesh or point cloud (docs/body.md).

The names below are imported on first use (`hitogata.lazy`): rebuilding a fitted
body's detail does not load the scan fitting.
"""

from typing import TYPE_CHECKING

from hitogata.lazy import lazy_names

if TYPE_CHECKING:
    from hitogata.made_to_measure.scan_fit.detail import detailed_body
    from hitogata.made_to_measure.scan_fit.scan import Scan, make_scan
    from hitogata.made_to_measure.scan_fit.scanfit import ScanFit, fit_scan

__all__ = ["Scan", "ScanFit", "detailed_body", "fit_scan", "make_scan"]
__getattr__, __dir__ = lazy_names(globals(), {
    "detailed_body": "hitogata.made_to_measure.scan_fit.detail",
    "Scan": "hitogata.made_to_measure.scan_fit.scan",
    "make_scan": "hitogata.made_to_measure.scan_fit.scan",
    "ScanFit": "hitogata.made_to_measure.scan_fit.scanfit",
    "fit_scan": "hitogata.made_to_measure.scan_fit.scanfit",
})
