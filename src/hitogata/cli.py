"""The `hitogata` command: thin shells over the library calls (one module per command).

Every mistake ends the same way, whatever the command: one line on stderr
(`hitogata: error: …` naming the file, entry, value and what is
allowed), exit status 2, nothing written. The output a command declares
(`commands.paths.add_output`) is checked before any work and a folder is
written through a staging folder, so Ctrl-C (exit 130) leaves nothing behind.

Start-up is lazy: `hitogata --help` imports no command module; a command's
module (and the library under it) is imported only when that command runs.
"""

from __future__ import annotations

import argparse
import errno
import importlib
import os
import re
import signal
import sys
import threading
import warnings
from collections.abc import Sequence
from types import FrameType
from typing import NoReturn

from hitogata.errors import HitogataError, one_line, warnings_as_lines

# name → (module, one-line help); the module's `register(subparsers)` adds the full parser.
COMMANDS = {
    "body": ("hitogata.commands.body", "build a body from sex, age, stature and mass, and write it"),
    "cache": ("hitogata.commands.cache", "the elastic models kept on disk between runs: --info or --clear"),
    "demo": ("hitogata.commands.demo", "run the main job on the built-in default bodies"),
    "dress": ("hitogata.commands.dress", "put a stretch garment on the body: its contact pressure on the skin"),
    "ease": ("hitogata.commands.ease", "dynamic ease and fabric stretch of a body through mobility motions"),
    "fit": ("hitogata.commands.fit", "fit the body to a scan (OBJ/PLY mesh or point cloud) and write it"),
    "fit-report": ("hitogata.commands.fit_report", "a self-contained HTML fit report of a body through motions"),
    "identify": ("hitogata.commands.identify",
                 "fit the tissue constants to measured people and write them as a materials file"),
    "measure": ("hitogata.commands.measure", "apparel measurements of a body (a hitogata .glb or the body options)"),
    "modes": ("hitogata.commands.modes", "the elastic body's lowest vibration modes: CSV, VTU (ParaView), pictures"),
    "motion": ("hitogata.commands.motion", "import a BVH motion onto the skeleton, or export a scenario's motion as BVH"),
    "pose": ("hitogata.commands.pose", "pose a body by muscle contractions or joint angles and write it"),
    "simulate": ("hitogata.commands.simulate", "run a scenario (TOML) of muscle contractions and joint angles"),
    "skeleton": ("hitogata.commands.skeleton",
                 "draw the posed 65-part skeleton, front and side, optionally in its skin"),
    "study": ("hitogata.commands.study", "run a population study (bodies x motions) on dask.distributed"),
    "validate": ("hitogata.commands.validate",
                 "every published measurement of the validation set beside the model's answer"),
    "view": ("hitogata.commands.view", "open the interactive web viewer: pose the body by its muscles"),
}
RESEND_SECONDS = 0.05  # a stop that came inside an import is tried again this much later
NEGATIVE_VALUE = re.compile(r"^-\.?\d")  # '-5kg', '-.5': a value, not an option


class OneLineParser(argparse.ArgumentParser):
    """argparse, but a mistake is one line (no usage block) and exit status 2; options are spelt out
    in full (`--stat` is not taken for `--stature`: a later option could make it mean another)."""

    def __init__(self, *args, **kwargs) -> None:
        kwargs.setdefault("allow_abbrev", False)
        super().__init__(*args, **kwargs)

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"hitogata: error: {one_line(message)}\n")


def version() -> str:
    from importlib.metadata import PackageNotFoundError
    from importlib.metadata import version as installed

    try:
        return installed("hitogata")
    except PackageNotFoundError:
        return "unknown (not installed)"


class Version(argparse.Action):
    """--version, looked up only when asked (reading the installed metadata takes tens of ms)."""

    def __init__(self, option_strings: Sequence[str], dest: str = argparse.SUPPRESS, help: str | None = None) -> None:
        super().__init__(option_strings, dest=dest, default=argparse.SUPPRESS, nargs=0, help=help)

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace, values: object,
                 option_string: str | None = None) -> None:
        print(f"hitogata {version()}")
        parser.exit()


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The parser; only `command`'s module is imported (the others are listed by name and help)."""
    parser = OneLineParser(prog="hitogata", description="A posable human body model for apparel design.")
    parser.add_argument("--version", action=Version, help="show the installed version and exit")
    sub = parser.add_subparsers(dest="command", required=True, metavar="{" + ",".join(COMMANDS) + "}")
    for name, (module, help) in COMMANDS.items():
        if name == command:
            importlib.import_module(module).register(sub)
        else:
            sub.add_parser(name, help=help, add_help=False)
    return parser


def joined_negative_values(argv: list[str]) -> list[str]:
    """`--mass -5kg` → `--mass=-5kg`, so argparse takes a negative value for a value, not an option."""
    out: list[str] = []
    for token in argv:
        if out and NEGATIVE_VALUE.match(token) and out[-1].startswith("--") and "=" not in out[-1]:
            out[-1] = f"{out[-1]}={token}"
        else:
            out.append(token)
    return out


def main(argv: Sequence[str] | None = None) -> int:
    argv = joined_negative_values(list(sys.argv[1:] if argv is None else argv))
    command = next((a for a in argv if not a.startswith("-")), None)
    command = command if command in COMMANDS else None
    from hitogata.commands.paths import prepared_output

    stops = StopSignals()
    try:
        with warnings.catch_warnings(), stops:
            warnings_as_lines()
            try:
                args = build_parser(command).parse_args(argv)
            except SystemExit as done:  # --help, --version, or argparse's one-line error (OneLineParser)
                return int(done.code or 0)
            if getattr(args, "no_cache", False):  # `add_cache_argument`: for this run and the processes it starts
                from hitogata.disk_cache import NO_CACHE_ENV

                os.environ[NO_CACHE_ENV] = "1"
            with prepared_output(args):
                args.run(args)
                if stops.received and getattr(args, "workdir", None) is not None:
                    raise stops.exception()  # a library swallowed the stop: the folder is not kept
            if stops.received:  # the same, for a command whose files were already in place
                print(f"hitogata: {stops.word()} after the output was written", file=sys.stderr)
                return 128 + stops.received
    except HitogataError as err:
        print(f"hitogata: error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as stop:
        # A second signal while the interpreter winds down would kill it (no message): from here
        # on the command is only exiting, so let it finish.
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
        terminated = isinstance(stop, Terminated)
        print(f"hitogata: {'terminated' if terminated else 'interrupted'}; nothing written", file=sys.stderr)
        return 128 + (signal.SIGTERM if terminated else signal.SIGINT)
    except BrokenPipeError:  # output piped into `head` and the like: not an error
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    except OSError as err:
        if err.errno not in (errno.ENOSPC, errno.EDQUOT, errno.EROFS, errno.EIO):
            raise
        # the disk filled (or failed) while writing: the writers have removed what they staged
        print(f"hitogata: error: {err.filename or 'output'}: cannot write ({err.strerror}); nothing written",
              file=sys.stderr)
        return 2
    return 0


class Terminated(KeyboardInterrupt):
    """SIGTERM (what `timeout`, systemd and CI send), taken like Ctrl-C: the command stops, nothing left behind."""


class StopSignals:
    """While the command runs (main thread): Ctrl-C raises KeyboardInterrupt and SIGTERM `Terminated`.

    Not inside an import: an exception raised there can be swallowed (trimesh's optional imports
    catch BaseException) or break the import machinery itself; the signal is sent again 50 ms later
    until the import is done. And the stop is remembered, so one a library swallowed all the same
    still ends the command as stopped once its work returns.
    """

    def __init__(self) -> None:
        self.received: int = 0
        self.previous: dict[int, object] = {}

    def __enter__(self) -> "StopSignals":
        if threading.current_thread() is threading.main_thread():
            for signum in (signal.SIGINT, signal.SIGTERM):
                self.previous[signum] = signal.signal(signum, self._stop)
        return self

    def __exit__(self, *exc: object) -> None:
        for signum, handler in self.previous.items():
            signal.signal(signum, handler)  # type: ignore[arg-type]

    def _stop(self, signum: int, frame: FrameType | None) -> None:
        self.received = signum
        if _importing(frame):
            again = threading.Timer(RESEND_SECONDS, os.kill, (os.getpid(), signum))
            again.daemon = True
            again.start()
            return
        raise self.exception()

    def exception(self) -> KeyboardInterrupt:
        return Terminated() if self.received == signal.SIGTERM else KeyboardInterrupt()

    def word(self) -> str:
        return "terminated" if self.received == signal.SIGTERM else "interrupted"


def _importing(frame: FrameType | None) -> bool:
    """Whether the interrupted code runs inside an import (importlib's frames on the stack)."""
    while frame is not None:
        if frame.f_code.co_filename.startswith("<frozen importlib"):
            return True
        frame = frame.f_back
    return False


if __name__ == "__main__":
    sys.exit(main())
