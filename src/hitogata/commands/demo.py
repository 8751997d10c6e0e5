"""`hitogata demo`: the main job on the built-in default bodies.

The default female and male bodies with their figures, then the paper's
experiment on the whole female body (`dynamics.demo.run_demo`): the rectus
abdominis stretched and released, and trunk flexion with the arms raised forward.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from hitogata.body import default_body
from hitogata.commands.body import figures_line
from hitogata.dynamics.demo import run_demo
from hitogata.export.atomic import write_bytes_atomically
from hitogata.export.body_files import body_figures, write_body


def run(args: argparse.Namespace) -> None:
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    summary = {}
    for sex in ("female", "male"):
        body = default_body(sex)
        for suffix in (".glb", ".obj"):
            write_body(out / f"default_{sex}{suffix}", body)
        summary[sex] = {"age_years": body.params.age, **body_figures(body)}
        print(figures_line(f"default {sex}", body))
    write_bytes_atomically(out / "summary.json", json.dumps(summary, indent=2).encode())
    print(run_demo(out, progress=True))
    print(f"wrote {out}/")


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("demo", help="run the main job on the built-in default bodies")
    parser.add_argument("--out", default="demo", help="output folder; default ./demo")
    parser.set_defaults(run=run)
