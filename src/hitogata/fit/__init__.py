"""A body from a scan: register the body model to a triangle mesh or point cloud (docs/body.md)."""

from hitogata.fit.detail import detailed_body
from hitogata.fit.scan import Scan, make_scan
from hitogata.fit.scanfit import ScanFit, fit_scan

__all__ = ["Scan", "ScanFit", "detailed_body", "fit_scan", "make_scan"]
