"""The paths a user gives the `hitogata` command, checked before any work; output staged, then renamed.

One mechanism for every sub-command:

- an input is an argparse `type=` (`input_path`): it must exist, be the right
  kind (file or folder) and be readable, or parsing stops with one line;
- the output is declared once with `add_output` (a file or a folder, the
  allowed suffixes, `--force`); `cli.main` checks it (`check_output`) before
  the command runs: a name is given, it is the right kind, its place can be
  written (probed by creating a file there), and an existing file, a
  non-empty folder or a symbolic link (even a dangling one or a loop) is not
  replaced without `--force`;
- while the command runs it holds a lock on its output (`output_lock`, a
  hidden `.NAME.lock` beside it, locked with flock): a second run writing the
  same output at the same time stops at once with one line; the holder
  removes the staging folders and temporary files an earlier, killed run of
  its own left beside the target;
- a folder output is written into a temporary folder beside the target
  (`args.workdir`) and renamed to the target only when the command has
  finished (`staged_folder`): an error, Ctrl-C or SIGTERM leaves nothing
  behind, and a target that another program filled meanwhile is not merged
  into (unless `--force`). A file output is written atomically by
  `hitogata.export.atomic`.
"""

from __future__ import annotations

import argparse
import contextlib
import difflib
import errno
import glob
import os
import secrets
import shutil
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Literal

from hitogata.errors import HitogataError, excerpt

try:
    import fcntl
except ImportError:  # not POSIX
    fcntl = None  # type: ignore[assignment]
from hitogata.export.atomic import DISK_ERRORS, DiskError, disk_error, stale_temporaries

PathKind = Literal["file", "folder"]
# what the commands write as files: a new folder named like one is a mistake (`--size-chart … --out sizes.glb`)
FILE_SUFFIXES = (".glb", ".obj", ".ply", ".csv", ".json", ".png", ".html", ".toml", ".bvh", ".npz", ".vtu", ".txt")


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
        if not path.exists() and names is not None:
            shipped = sorted(known)
            close = [n for n in shipped if text and text in n] or difflib.get_close_matches(text, shipped, n=1)
            hint = f"did you mean {close[0]}? " if close else ""
            raise argparse.ArgumentTypeError(f"{excerpt(text)}: no such file; {hint}allowed {allowed} or a shipped name: "
                                             f"{listing(shipped, 150)}")
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


def listing(names: list[str], room: int) -> str:
    """`names` comma-separated within about `room` characters, the rest counted."""
    shown: list[str] = []
    for name in names:
        if shown and len(", ".join([*shown, name])) > room:
            return f"{', '.join(shown)} and {len(names) - len(shown)} more"
        shown.append(name)
    return ", ".join(shown)


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
    if path.is_symlink() and not force:
        raise HitogataError(f"--out {out}: is a symbolic link ({link_state(path)}); pass --force to replace the link")
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
    if not path.exists() and path.suffix.lower() in FILE_SUFFIXES:
        raise HitogataError(f"--out {out}: names a {path.suffix} file; this command writes a folder (several files): "
                            f"allowed a folder name, e.g. {path.with_suffix('')}")
    if path.is_dir() and any(path.iterdir()) and not force:
        raise HitogataError(f"--out {out}: the folder is not empty; name a new folder or pass --force")
    ancestor = _existing_ancestor(path)
    if not ancestor.is_dir():
        raise HitogataError(f"--out {out}: {ancestor} is not a folder; allowed a folder")
    _probe(path if path.is_dir() else ancestor, out)
    return path


def link_state(path: Path) -> str:
    """Where a symbolic link leads, in words."""
    try:
        destination = path.resolve(strict=True)
    except RuntimeError:
        return "a loop"
    except OSError as err:
        return "a loop" if err.errno == errno.ELOOP else f"dangling, to {os.readlink(path)}"
    return f"to {destination}"


@contextlib.contextmanager
def output_lock(target: Path) -> Iterator[None]:
    """Hold the lock on `target` (a hidden `.NAME.lock` beside it) or stop with one line if another run does.

    Holding it, stale staging folders and temporary files of `target` are removed: no other run of
    ours is writing them.
    """
    if target.parent.is_dir():
        lock = target.parent / f".{target.name}.lock"
    else:  # a folder to be made in folders not made yet: the lock goes in the nearest that exists
        ancestor = _existing_ancestor(target)
        lock = ancestor / f".{'%2F'.join(target.absolute().relative_to(ancestor).parts)}.lock"
    while True:
        fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o666)
        try:
            if fcntl is not None:  # POSIX; elsewhere the lock file is made but not locked
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            raise HitogataError(f"--out {target}: another hitogata command is writing it now; wait for it to "
                                "finish or choose another --out") from None
        try:
            same = os.fstat(fd).st_ino == os.stat(lock).st_ino  # not a lock file its last holder removed
        except FileNotFoundError:
            same = False
        if same:
            break
        os.close(fd)
    try:
        for stale in stale_staging(target):
            shutil.rmtree(stale, ignore_errors=True)
        for stale_file in stale_temporaries(target):
            stale_file.unlink(missing_ok=True)
        yield
    finally:
        lock.unlink(missing_ok=True)
        os.close(fd)


def stale_staging(target: Path) -> list[Path]:
    """Staging folders of `target` a stopped run left (`.NAME.partial-XXXX/`)."""
    if not target.parent.is_dir():
        return []
    return [p for p in target.parent.glob(f".{glob.escape(target.name)}.partial-*") if p.is_dir()]


@contextlib.contextmanager
def staged_folder(target: Path, force: bool = True) -> Iterator[Path]:
    """A temporary folder beside `target` to write into; renamed (or merged, `force`) into `target` on success only.

    A target another program filled while the command ran is not merged into unless `force`.
    """
    target.parent.mkdir(parents=True, exist_ok=True)
    staging = target.parent / f".{target.name}.partial-{secrets.token_hex(4)}"
    try:  # made inside the try: a stop arriving just after it is made still removes it
        staging.mkdir()
        yield staging
        if target.is_dir() and any(target.iterdir()) and not force:
            raise HitogataError(f"--out {target}: the folder was filled by another program while this command ran; "
                                "nothing written (name a new folder or pass --force)")
    except (OSError, DiskError) as err:  # a full disk names the output, not the staging folder
        shutil.rmtree(staging, ignore_errors=True)
        if isinstance(err, DiskError) or err.errno in DISK_ERRORS:
            raise disk_error(target, err) from None
        raise
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
    with output_lock(path):
        if spec.kind == "file":
            yield
            return
        with staged_folder(path, args.force) as staging:
            args.workdir = staging
            yield
