"""`hitogata fit`: register the body to a scan (OBJ/PLY mesh or point cloud) and write the fitted body.

The fitted body goes to --out (a skinned GLB that `hitogata measure` and the
Python API read back with its per-vertex detail); the fit report (errors,
regions, measurements of scan and body side by side) is printed and written
as JSON beside it (`fitted.glb` → `fitted.json`).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from hitogata.commands.paths import add_output, input_path
from hitogata.errors import HitogataError
from hitogata.export.scans import SCAN_SUFFIXES
from hitogata.made_to_measure.scan_fit.scan import UNITS

# m: a scan the model cannot come this close to (median, scan to body) is not of a standing person;
# a scan of a person standing in any pose the fit follows comes within 2 mm (tests/made_to_measure/test_fit_scan.py,
# tests/made_to_measure/test_fit_pose.py)
MAX_MEDIAN = 0.025


def run(args: argparse.Namespace) -> None:
    from hitogata.body.model import sex_value
    from hitogata.commands.body import figures_line
    from hitogata.export.atomic import write_files_together
    from hitogata.export.body_files import body_glb_bytes
    from hitogata.export.scans import read_scan
    from hitogata.made_to_measure.scan_fit import fit_scan
    from hitogata.report.scan_fit import fit_summary, fit_text, summary_bytes

    sex_value(args.sex)
    report = Path(args.out).with_suffix(".json")
    if report.exists() and not args.force:
        raise HitogataError(f"--out {args.out}: the report {report} exists; pass --force to write over it")
    scan = read_scan(args.scan, args.units)
    fit = fit_scan(scan, args.sex, detail=not args.no_detail)
    if fit.model_error.median > MAX_MEDIAN:
        raise HitogataError(f"{args.scan}: the body model comes no closer than a median {fit.model_error.median * 1000:.0f} "
                            f"mm to the scan; allowed a scan of a standing person (a fit comes within "
                            f"{MAX_MEDIAN * 1000:.0f} mm); nothing written")
    summary = fit_summary(fit, str(args.scan), scan.unit)
    path = Path(args.out)
    write_files_together({path: body_glb_bytes(fit.body), report: summary_bytes(summary)})  # both or neither
    print(f"{args.scan}: {len(scan.points)} points{' (mesh)' if scan.faces is not None else ''}, in {scan.unit}")
    print(fit_text(summary))
    print(figures_line(str(path), fit.body))
    print(f"wrote {path} and {report}")


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("fit", help="fit the body to a scan (OBJ/PLY mesh or point cloud) and write it")
    parser.add_argument("scan", type=input_path("file", suffixes=SCAN_SUFFIXES),
                        help="the scan: an .obj or .ply triangle mesh or point cloud of a standing person")
    parser.add_argument("--sex", required=True, help="female, male, or 0 (female) … 1 (male)")
    parser.add_argument("--units", choices=tuple(UNITS), default=None,
                        help="the scan's unit; default: found from its extent (a person is 1.4–2.1 m tall)")
    parser.add_argument("--no-detail", action="store_true",
                        help="the shape model alone, without the per-vertex detail")
    add_output(parser, "file", "the fitted body: a .glb (skinned, with rig); its report goes beside it as .json",
               (".glb",))
    parser.set_defaults(run=run)
