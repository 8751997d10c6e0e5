"""The paths a user gives the `hitogata` command, checked before any work; output staged, then renamed.

One mechanism for every sub-command:

- an input is an argparse `type=` (`input_path`): it must exist, be the right
  kind (file or folder) and be readable, or parsing stops with one line;
- the output is declared once with `add_output` (a file or a folder, the
  allowed suffixes, `--force`); `cli.main` checks it (`check_output`) before
  the command runs: a name is given, it is the right kind, its place can be
  written (probed by creating a file there), and an existing file or a
  non-empty folder is not replaced without `--force`;
- a folder output is written into a temporary folder beside the target
  (`args.workdir`) and renamed to the target only when the command has
  finished (`staged_folder`): an error or Ctrl-C leaves nothing behind. A
  file output is written atomically by `hitogata.export.atomic`.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import secrets
import shutil
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Literal

from hitogata.errors import HitogataError

PathKind = Literal["file", "folder"]


@dataclass(frozen=True)
class Output:
    """What a command's --out names: a file (with these suffixes) or a folder."""

    kind: PathKind
    suffixes: tuple[str, ...] = ()
    required: bool = True  # False: the command may run without one (e.g. `pose --list`)

    def allowed(self) -> str:
        if self.kind == "folder":
            return "a folder"
        return f"a file ({', '.join(self.suffixes)})" if self.suffixes else "a file"


def add_output(parser: argparse.ArgumentParser, kind: PathKind, help: str, suffixes: tuple[str, ...] = (),
               required: bool = True, default: str | None = None) -> None:
    """--out and --force, and the declaration `cli.main` checks before the command runs."""
    parser.add_argument("--out", required=required and default is None, default=default, help=help)
    what = "file" if kind == "file" else "non-empty folder (files of the same name are replaced, others kept)"
    parser.add_argument("--force", action="store_true", help=f"write over an existing {what}")
    parser.set_defaults(output=Output(kind, suffixes, required or default is not None))


def input_path(*kinds: PathKind, suffixes: tuple[str, ...] = (), names: Callable[[], dict[str, Path]] | None = None
               ) -> Callable[[str], Path]:
    """An argparse type: an existing, readable file or folder (of these kinds; files with these suffixes).

    `names`: short names that stand for shipped files (e.g. the scenarios).
    """
    def check(text: str) -> Path:
        if names is not None and text in (known := names()):
            return known[text]
        path = Path(text)
        allowed = " or ".join(f"a {k}" + (f" ({', '.join(suffixes)})" if k == "file" and suffixes else "")
                              for k in kinds)
        if not text:
            raise argparse.ArgumentTypeError(f"'': allowed {allowed}")
        if not path.exists():
            raise argparse.ArgumentTypeError(f"{text}: no such file or folder; allowed {allowed}")
        kind: PathKind = "folder" if path.is_dir() else "file"
        if kind not in kinds:
            raise argparse.ArgumentTypeError(f"{text}: is a {kind}; allowed {allowed}")
        if kind == "file" and suffixes and path.suffix.lower() not in suffixes:
            raise argparse.ArgumentTypeError(f"{text}: unknown file suffix {path.suffix!r}; allowed {allowed}")
        if not os.access(path, os.R_OK | (os.X_OK if kind == "folder" else 0)):
            raise argparse.ArgumentTypeError(f"{text}: cannot be read (permission denied)")
        return path

    return check


def _probe(folder: Path, what: str) -> None:
    """Fail with one line unless a file can be created in `folder` (root ignores permission bits: try it)."""
    probe = folder / f".hitogata-probe-{secrets.token_hex(4)}"
    try:
        probe.touch(exist_ok=False)
        probe.unlink()
    except OSError as err:
        raise HitogataError(f"--out {what}: cannot write in {folder} ({err.strerror or err})") from None


def _existing_ancestor(path: Path) -> Path:
    for parent in path.absolute().parents:
        if parent.exists():
            return parent
    return Path("/")


def check_output(out: str | None, spec: Output, force: bool) -> Path:
    """The output path, if it can be written as `spec` says; otherwise one line naming what is allowed."""
    if out is None or not str(out).strip():
        raise HitogataError(f"--out {out!r}: allowed {spec.allowed()} name")
    path = Path(out)
    if spec.kind == "file":
        if spec.suffixes and path.suffix.lower() not in spec.suffixes:
            allowed = ", ".join(spec.suffixes)
            raise HitogataError(f"--out {out}: unknown file suffix {path.suffix!r}; allowed: {allowed}")
        if path.is_dir():
            raise HitogataError(f"--out {out}: is a folder; allowed {spec.allowed()}")
        if path.exists() and not force:
            raise HitogataError(f"--out {out}: the file exists; pass --force to write over it")
        if not path.parent.is_dir():
            what = "is not a folder" if path.parent.exists() else "does not exist"
            raise HitogataError(f"--out {out}: {path.parent} {what}; allowed a file in an existing folder")
        _probe(path.parent, out)
        return path
    if path.exists() and not path.is_dir():
        raise HitogataError(f"--out {out}: is a file; allowed a folder (new, empty, or with --force)")
    if path.is_dir() and any(path.iterdir()) and not force:
        raise HitogataError(f"--out {out}: the folder is not empty; name a new folder or pass --force")
    ancestor = _existing_ancestor(path)
    if not ancestor.is_dir():
        raise HitogataError(f"--out {out}: {ancestor} is not a folder; allowed a folder")
    _probe(path if path.is_dir() else ancestor, out)
    return path


@contextlib.contextmanager
def staged_folder(target: Path) -> Iterator[Path]:
    """A temporary folder beside `target` to write into; renamed (or merged) into `target` on success only."""
    target.parent.mkdir(parents=True, exist_ok=True)
    staging = target.parent / f".{target.name}.partial-{secrets.token_hex(4)}"
    staging.mkdir()
    try:
        yield staging
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    if target.is_dir() and any(target.iterdir()):  # --force: same names replaced, other files kept
        for item in staging.iterdir():
            destination = target / item.name
            if destination.is_dir():
                shutil.rmtree(destination)
            os.replace(item, destination)
        staging.rmdir()
        return
    if target.is_dir():
        target.rmdir()
    os.replace(staging, target)


@contextlib.contextmanager
def prepared_output(args: argparse.Namespace) -> Iterator[None]:
    """Check the command's declared --out before it runs; give a folder command its staging folder."""
    spec: Output | None = getattr(args, "output", None)
    if spec is None or (args.out is None and not spec.required):
        yield
        return
    path = check_output(args.out, spec, args.force)
    if spec.kind == "file":
        yield
        return
    with staged_folder(path) as staging:
        args.workdir = staging
        yield
