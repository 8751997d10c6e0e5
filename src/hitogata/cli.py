"""The `hitogata` command: thin shells over the library calls (one module per command).

A user's mistake prints one line (`hitogata: error: …`) and exits with status 2;
nothing is written.
"""

from __future__ import annotations

import argparse
import os
import sys
from typing import Sequence

from hitogata.commands import body, demo, ease, measure, modes, motion, pose, simulate, skeleton, view
from hitogata.errors import HitogataError

COMMANDS = (body, demo, ease, measure, modes, motion, pose, simulate, skeleton, view)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="hitogata", description="A posable human body model for apparel design.")
    sub = parser.add_subparsers(dest="command", required=True)
    for command in COMMANDS:
        command.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        args.run(args)
    except HitogataError as err:
        print(f"hitogata: error: {err}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # output piped into `head` and the like: not an error
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    return 0


if __name__ == "__main__":
    sys.exit(main())
