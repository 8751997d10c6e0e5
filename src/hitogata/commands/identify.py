"""`hitogata identify`: the tissue constants fitted to measured people, written as a materials file."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from hitogata.commands.args import add_cache_argument, add_materials_argument
from hitogata.commands.paths import add_output, input_path
from hitogata.commands.validate import names
from hitogata.export.atomic import write_bytes_atomically


def run(args: argparse.Namespace) -> None:
    from hitogata.elastic.materials import load_materials
    from hitogata.validation import load_dataset
    from hitogata.validation.identify import IDENTIFIABLE, identifiable, identify
    from hitogata.validation.identify_report import materials_toml, report_lines

    everything = load_dataset(args.data)
    rows, kinds = names(args.rows, "--rows"), names(args.kinds, "--kinds")
    chosen = identifiable(everything.select(rows, kinds or (() if rows else IDENTIFIABLE)))
    start_materials = load_materials("literature" if args.materials is None else str(args.materials))
    kinds_fitted = {r.kind for r in chosen.rows}
    rest = tuple(r for r in everything.rows if r.kind in kinds_fitted and r not in chosen.rows)
    held_out = type(everything)(everything.path, everything.sources, rest) if rest else None
    start = time.perf_counter()
    fit = identify(chosen, start_materials, held_out, None if args.quiet else print)
    for line in report_lines(fit):
        print(line)
    out = Path(args.out)
    write_bytes_atomically(out, materials_toml(fit, start_materials, "the shipped validation set" if args.data is None else everything.path).encode())
    print(f"wrote {out} in {time.perf_counter() - start:.0f} s (use it with --materials {out})")


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("identify", help="fit the tissue constants (moduli, density, damping) to measured people "
                                             "and write them as a materials file")
    parser.add_argument("--data", type=input_path("file", suffixes=(".toml",)), default=None,
                        help="a validation file (TOML); default the shipped set")
    parser.add_argument("--rows", default=None, help="fit these row ids only (comma-separated); the file's other rows "
                                                     "of the same kinds are held out and predicted")
    parser.add_argument("--kinds", default=None,
                        help="fit rows of these kinds only (comma-separated; default stiffness,frequency,damping)")
    add_materials_argument(parser, "the starting materials (the bounds are the literature's ranges)",
                           default_text="literature")
    parser.add_argument("--quiet", action="store_true", help="no progress lines")
    add_output(parser, "file", "the materials file to write (.toml)", suffixes=(".toml",))
    add_cache_argument(parser)
    parser.set_defaults(run=run)
