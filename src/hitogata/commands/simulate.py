"""`hitogata simulate`: run a scenario file and write its motion, pictures and summary."""

from __future__ import annotations

import argparse
import sys

from hitogata.dynamics.run import run_scenario
from hitogata.dynamics.scenario import load_scenario, shipped_scenarios


def run(args: argparse.Namespace) -> None:
    shipped = shipped_scenarios()
    path = shipped[args.scenario] if args.scenario in shipped else args.scenario
    scenario = load_scenario(path)
    summary = run_scenario(scenario, args.out, progress=sys.stderr.isatty() and not args.quiet)
    print(summary.text(), end="")
    print(f"wrote {len(summary.files) + 2} files to {args.out}/")


def register(sub: argparse._SubParsersAction) -> None:
    names = ", ".join(sorted(shipped_scenarios()))
    parser = sub.add_parser("simulate", help="run a scenario (TOML) of muscle contractions and joint angles")
    parser.add_argument("scenario", help=f"a scenario file (docs/scenarios.md) or a shipped one: {names}")
    parser.add_argument("--out", default="results", help="output folder; default ./results")
    parser.add_argument("--quiet", action="store_true", help="no progress bars")
    parser.set_defaults(run=run)
