"""The documented scan-fitting names at their old path, `hitogata.fit`: each is
`hitogata.made_to_measure.scan_fit`'s, with a DeprecationWarning on import; write
`from hitogata.made_to_measure.scan_fit import fit_scan` (docs/howto/fit-a-scan.md)."""

from typing import TYPE_CHECKING

from hitogata.lazy import moved_names

if TYPE_CHECKING:
    from hitogata.made_to_measure.scan_fit import Scan, ScanFit, detailed_body, fit_scan, make_scan

__all__ = ["Scan", "ScanFit", "detailed_body", "fit_scan", "make_scan"]
__getattr__, __dir__ = moved_names(globals(), "hitogata.made_to_measure.scan_fit", __all__)
