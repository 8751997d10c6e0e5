"""`hitogata measure`: ISO 8559-1 measurements (and skin strain for a posture) of a body.

INPUT is a GLB written by `hitogata body` or `hitogata pose` (its extras hold the
shape), an .obj/.ply of `hitogata pose` with its .json (the pose), a results
folder or `*_sequence.npz` of `hitogata simulate` (measurements and zone strains
over time), or nothing (the body options). The report goes to --out.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from hitogata.body.model import Body
from hitogata.commands.args import add_body_arguments, refuse_body_options
from hitogata.commands.body import body_from_args
from hitogata.commands.paths import add_output, input_path
from hitogata.errors import HitogataError
from hitogata.export.body_files import body_from_extras
from hitogata.export.glb_read import read_glb_skin
from hitogata.measure import Measurements, measure
from hitogata.report.measurements import measure_report, measurement_table


REST_TOLERANCE = 1e-5  # m: a GLB stores float32 positions; closer than this to rest is the rest pose


def body_from_file(path: Path) -> tuple[Body, np.ndarray | None, np.ndarray | None, np.ndarray | None]:
    """The body a hitogata file describes, and when posed its skin vertices, rig joints and fine skin.

    A `hitogata pose` GLB holds the rest skin with the pose as joint rotations and
    the pose's angles in its extras: the posture is rebuilt from those. An .obj/.ply
    of `hitogata pose` is read with its JSON sidecar (`hitogata.export.posed_mesh`).
    """
    if path.suffix.lower() in (".obj", ".ply"):
        from hitogata.export.posed_mesh import read_posed_mesh  # the posing: only for a posed file

        return read_posed_mesh(path)
    skin = read_glb_skin(path)
    extras = skin.extras or {}
    body = body_from_extras(path, extras)
    if skin.vertices.shape != body.vertices.shape:
        raise HitogataError(f"{path}: {len(skin.vertices)} vertices, allowed {len(body.vertices)} (the hitogata skin)")
    if "angles_rad" in extras:
        from hitogata.export.posed_mesh import posture

        return body, *posture(body, np.asarray(extras["angles_rad"], dtype=float))
    at_rest = np.abs(skin.vertices - body.vertices).max() < REST_TOLERANCE
    return body, (None if at_rest else skin.vertices), None, None


def measure_results(path: Path, out: Path, workdir: Path) -> None:
    """Measurements and zone strains over time of a simulated motion: CSV and plot."""
    from hitogata.export.motion_files import find_sequence, read_sequence_body  # the dynamics: only for results
    from hitogata.measure.timeseries import measure_sequence
    from hitogata.report.series import write_series

    body, arrays = read_sequence_body(find_sequence(path) if path.is_dir() else path)
    series = measure_sequence(body, arrays["times"], arrays["vertices"], arrays["joints"])
    written = write_series(series, workdir, title=str(path))
    last = {name: series.values[-1, k] for k, name in enumerate(series.names)}
    print(measurement_table(Measurements(**last), reference=measure(body)))
    print(f"{len(series.times)} frames; wrote {', '.join(p.name for p in written.values())} in {out}/")


def run(args: argparse.Namespace) -> None:
    out, workdir, given = Path(args.out), args.workdir, args.input
    if given is not None:
        refuse_body_options(args, f"the body comes from {given}")
    if given is not None and (given.is_dir() or given.suffix.lower() == ".npz"):
        measure_results(given, out, workdir)
        return
    if given is not None:
        body, vertices, joints, fine = body_from_file(given)
    else:
        body, vertices, joints, fine = body_from_args(args), None, None, None
    report = measure_report(body, workdir, vertices=vertices, joints=joints, title=str(given or ""),
                            fine_vertices=fine)
    print(measurement_table(report.measurements, reference=None if vertices is None else report.rest))
    print(f"wrote {', '.join(p.name for p in report.files.values())} in {out}/")


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("measure", help="apparel measurements of a body (a hitogata .glb or the body options)")
    parser.add_argument("input", nargs="?", default=None,
                        type=input_path("file", "folder", suffixes=(".glb", ".npz", ".obj", ".ply")),
                        help="a .glb written by `hitogata body` or `hitogata pose`, an .obj/.ply of `hitogata pose` "
                        "(with its .json), or a results folder / *_sequence.npz of `hitogata simulate`")
    add_body_arguments(parser)
    add_output(parser, "folder", "report folder: measurements.json/.csv/.png (created; a new or empty folder)")
    parser.set_defaults(run=run)
