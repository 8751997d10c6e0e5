"""`--body FILE.glb`: a body read from a hitogata GLB (`hitogata body`, `hitogata fit`) instead of the body options."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from hitogata.commands.args import refuse_body_options
from hitogata.commands.body import body_from_args
from hitogata.commands.paths import input_path

if TYPE_CHECKING:
    from hitogata.body.model import Body


def add_body_file(parser: argparse.ArgumentParser) -> None:
    """--body: the body of a GLB written by `hitogata body`, `hitogata fit` or `hitogata pose` (its rest body)."""
    parser.add_argument("--body", type=input_path("file", suffixes=(".glb",)), default=None,
                        help="the body of a .glb written by `hitogata body`, `hitogata fit` or `hitogata pose` "
                        "(its rest shape, with a fitted body's detail) instead of the body options")


def body_of(args: argparse.Namespace) -> Body:
    """The body --body names, or the one the body options describe."""
    path = getattr(args, "body", None)
    if path is None:
        return body_from_args(args)
    from hitogata.export.body_files import body_from_extras
    from hitogata.export.glb_read import read_glb_skin

    refuse_body_options(args, f"the body comes from {path}")
    return body_from_extras(path, read_glb_skin(path).extras or {})
