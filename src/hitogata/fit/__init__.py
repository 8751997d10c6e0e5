"""A body from a scan: register the body model to a triangle mesh or point cloud (docs/body.md).

The names below are imported on first use (`hitogata.lazy`): rebuilding a fitted
body's detail does not load the scan fitting.
"""

from typing import TYPE_CHECKING

from hitogata.lazy import lazy_names

if TYPE_CHECKING:
    from hitogata.fit.detail import detailed_body
    from hitogata.fit.scan import Scan, make_scan
    from hitogata.fit.scanfit import ScanFit, fit_scan

__all__ = ["Scan", "ScanFit", "detailed_body", "fit_scan", "make_scan"]
__getattr__, __dir__ = lazy_names(globals(), {
    "detailed_body": "hitogata.fit.detail",
    "Scan": "hitogata.fit.scan",
    "make_scan": "hitogata.fit.scan",
    "ScanFit": "hitogata.fit.scanfit",
    "fit_scan": "hitogata.fit.scanfit",
})
