"""`hitogata cache`: what the model cache holds, and emptying it (`hitogata.disk_cache`)."""

from __future__ import annotations

import argparse

from hitogata import disk_cache


def run(args: argparse.Namespace) -> None:
    if args.clear:
        entries, size = disk_cache.clear()
        print(f"removed {entries} entries ({size / 1e6:.0f} MB) from {disk_cache.cache_dir()}")
    else:
        print(disk_cache.info().summary())


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("cache", help="the elastic models kept on disk between runs: --info (default) or --clear")
    what = parser.add_mutually_exclusive_group()
    what.add_argument("--info", action="store_true", help="the cache's folder, entries, size and limit (default)")
    what.add_argument("--clear", action="store_true", help="remove every entry")
    parser.set_defaults(run=run)
