"""`hitogata simulate`: run a scenario file and write its motion, pictures and summary."""

from __future__ import annotations

import argparse
import sys
from dataclasses import replace

from hitogata.commands.args import add_cache_argument, add_materials_argument
from hitogata.commands.paths import add_output, input_path
from hitogata.motion.scenario import load_scenario, shipped_scenarios


def run(args: argparse.Namespace) -> None:
    from hitogata.elastic.materials import load_materials
    from hitogata.motion.checks import checked_scenario
    from hitogata.simulation.run import run_scenario

    given = None
    if args.body is not None:
        from hitogata.export.body_files import body_from_extras
        from hitogata.export.glb_read import read_glb_skin

        given = body_from_extras(args.body, read_glb_skin(args.body).extras or {})
    scenario = load_scenario(args.scenario)
    if args.materials is not None:  # the option over the scenario's [model].materials
        load_materials(args.materials)  # a bad file is said before any long work
        scenario = replace(scenario, model=replace(scenario.model, materials=str(args.materials)))
    scenario, body = checked_scenario(scenario, given)  # names and values, before the model
    summary = run_scenario(scenario, args.workdir, progress=sys.stderr.isatty() and not args.quiet, body=body,
                           contact=args.contact)
    print(summary.text(), end="")
    print(f"wrote {len(summary.files) + 2} files to {args.out}/")


def register(sub: argparse._SubParsersAction) -> None:
    names = ", ".join(sorted(shipped_scenarios()))
    parser = sub.add_parser("simulate", help="run a scenario (TOML) of muscle contractions and joint angles")
    parser.add_argument("scenario", type=input_path("file", suffixes=(".toml",), names=shipped_scenarios),
                        help=f"a scenario file (docs/scenarios.md) or a shipped one: {names}")
    add_output(parser, "folder", "output folder; default ./results (a new or empty folder)", default="results")
    parser.add_argument("--quiet", action="store_true", help="no progress bars")
    parser.add_argument("--contact", action="store_true",
                        help="resolve the skin's self-contact in every frame (no part passing into another, "
                        "the creases folded as a held pose's; 0.1-0.4 s a frame where skin meets: "
                        "docs/scenarios.md)")
    parser.add_argument("--body", type=input_path("file", suffixes=(".glb",)), default=None,
                        help="run on the body of a .glb written by `hitogata body` or `hitogata fit` "
                        "instead of the scenario's [body]")
    add_materials_argument(parser, "the tissue materials (over the scenario's [model].materials)")
    add_cache_argument(parser)
    parser.set_defaults(run=run)
