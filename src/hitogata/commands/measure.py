"""`hitogata measure`: ISO 8559-1 measurements (and skin strain for a posture) of a body.

The body comes from a GLB written by hitogata (its extras hold the shape) or
from the body options; the report (JSON, CSV, pictures) goes to --out.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from hitogata.body import Body
from hitogata.commands.args import add_body_arguments
from hitogata.commands.body import body_from_args
from hitogata.errors import HitogataError
from hitogata.export.body_files import body_from_extras
from hitogata.export.gltf import read_glb_skin
from hitogata.measure import measure
from hitogata.measure.cli_support import measure_report, measurement_table


REST_TOLERANCE = 1e-5  # m: a GLB stores float32 positions; closer than this to rest is the rest pose


def body_from_file(path: Path) -> tuple[Body, np.ndarray | None]:
    """The body a hitogata GLB describes, and its skin vertices when they are a posture."""
    if path.suffix.lower() != ".glb":
        raise HitogataError(f"{path}: allowed a .glb written by `hitogata body` (OBJ/PLY carry no shape)")
    if not path.is_file():
        raise HitogataError(f"{path}: no such file")
    skin = read_glb_skin(path)
    body = body_from_extras(path, skin.extras or {})
    if skin.vertices.shape != body.vertices.shape:
        raise HitogataError(f"{path}: {len(skin.vertices)} vertices, allowed {len(body.vertices)} (the hitogata skin)")
    at_rest = np.abs(skin.vertices - body.vertices).max() < REST_TOLERANCE
    return body, None if at_rest else skin.vertices


def run(args: argparse.Namespace) -> None:
    out = Path(args.out)
    if args.input is not None:
        body, vertices = body_from_file(Path(args.input))
    else:
        body, vertices = body_from_args(args), None
    out.mkdir(parents=True, exist_ok=True)
    written = measure_report(body, out, vertices=vertices, title=args.input or "")
    print(measurement_table(measure(body, vertices=vertices)))
    print(f"wrote {', '.join(p.name for p in written.values())} in {out}/")


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("measure", help="apparel measurements of a body (a hitogata .glb or the body options)")
    parser.add_argument("input", nargs="?", default=None, help="a .glb written by `hitogata body` (optional)")
    add_body_arguments(parser)
    parser.add_argument("--out", required=True, help="report folder: measurements.json/.csv/.png")
    parser.set_defaults(run=run)
