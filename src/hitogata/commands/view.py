"""`hitogata view`: the interactive web viewer, on this machine only unless asked otherwise."""

from __future__ import annotations

import argparse
import ipaddress
import time

from hitogata.commands.args import add_body_arguments
from hitogata.commands.body import body_from_args
from hitogata.commands.ease import add_garment_arguments, garment_from_args
from hitogata.commands.paths import input_path


def port_number(text: str) -> int:
    """A TCP port, 1–65535."""
    try:
        port = int(text)
    except ValueError:
        port = -1
    if not 1 <= port <= 65535:
        raise argparse.ArgumentTypeError(f"port {text!r}: allowed a whole number 1–65535")
    return port


def is_loopback(host: str) -> bool:
    """Whether only this machine can reach an address."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def run(args: argparse.Namespace) -> None:
    from hitogata.viewer.app import check_host, serve  # needs viser: only when a viewer starts

    check_host(args.host)  # before the body is built: a wrong address fails at once
    garment = garment_from_args(args)
    body = body_from_args(args)
    app = serve(body, host=args.host, port=args.port, garment=garment)
    if args.play:
        try:
            app.open_sequence(str(args.play))  # a broken file ends the command: nothing is served
        except BaseException:
            app.stop()
            raise
    print(f"hitogata viewer: {app.url}  (Ctrl-C to stop)", flush=True)
    if not is_loopback(args.host):
        print(f"hitogata viewer: listening on {args.host}: other machines can reach it", flush=True)
    try:
        while True:  # until Ctrl-C or SIGTERM: exit 130 or 143, as every command stopped so
            time.sleep(3600)
    finally:
        app.stop()


def register(sub: argparse._SubParsersAction) -> None:
    parser = sub.add_parser("view", help="open the interactive web viewer: pose the body by its muscles")
    add_body_arguments(parser)
    parser.add_argument("--host", default="127.0.0.1", help="address to listen on; default 127.0.0.1 (this machine only)")
    parser.add_argument("--port", type=port_number, default=8080, help="port; default 8080 (the next free one if taken)")
    parser.add_argument("--play", default=None, type=input_path("file", "folder", suffixes=(".npz", ".toml")),
                        help="a sequence (.npz), pose keyframes (.toml) or a results folder to load")
    add_garment_arguments(parser, "the skin's pressure colour map (with --fabric)")
    parser.set_defaults(run=run)
