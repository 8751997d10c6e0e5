"""`hitogata demo`: the main job on the built-in default bodies.

The default female and male bodies with their figures, then the paper's
experiment on the whole female body (`simulation.demo.run_demo`): the rectus
abdominis stretched and released, and trunk flexion with the arms raised forward.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from hitogata.body.model import default_body
from hitogata.commands.args import add_cache_argument
from hitogata.commands.body import figures_line
from hitogata.commands.paths import add_output
from hitogata.simulation.demo import run_demo
from hitogata.export.atomic import write_bytes_atomically
from hitogata.export.body_files import body_figures, write_body


def run(args: argparse.Namespace) -> None:
    out, work = Path(args.out), args.workdir
    summary = {}
    for sex in ("female", "male"):
        body = default_body(sex)
        for suffix in (".glb", ".obj"):
            write_body(work / f"default_{sex}{suffix}", body)
        summary[sex] = {"age_years": body.params.age, **body_figures(body)}
        print(figures_line(f"default {sex}", body))
    write_bytes_atomically(work / "summary.json", json.dumps(summary, indent=2).encode())
    print(run_demo(work, progress=sys.stderr.isatty()))
    print(f"wrote {out}/")


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("demo", help="run the main job on the built-in default bodies")
    add_output(parser, "folder", "output folder; default ./demo (a new or empty folder)", default="demo")
    add_cache_argument(parser)
    parser.set_defaults(run=run)
