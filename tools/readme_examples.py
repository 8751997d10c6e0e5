"""The README's command-line examples, as commands, in the order written; and a runner for them.

`examples(readme)` reads the first ```sh block under "## The command line",
joins continued lines, drops comments and splits `a; b` into two commands.
`python tools/readme_examples.py [DIR]` runs them all in DIR (a temporary
folder by default), with `hitogata` taken from this interpreter's
environment, skipping `hitogata view` (a server that runs until stopped); an example that
reads a skipped one's output is skipped with it.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
import tempfile
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"
SERVERS = ("view",)  # run until stopped: not run here


def examples(readme: Path = README) -> list[list[str]]:
    """Each example command as argv, in the README's order."""
    text = readme.read_text(encoding="utf-8")
    section = text[text.index("## The command line"):]
    block = re.search(r"```sh\n(.*?)```", section, re.S).group(1)
    commands = []
    for line in block.replace("\\\n", " ").splitlines():
        words = shlex.split(line, comments=True)
        while words:
            cut = next((i for i, w in enumerate(words) if w.endswith(";")), None)
            head, words = (words, []) if cut is None else (words[:cut + 1], words[cut + 1:])
            head[-1] = head[-1].removesuffix(";")
            if head and head[0] == "hitogata":
                commands.append(head)
    return commands


def run(folder: Path, skip: tuple[str, ...] = SERVERS) -> list[list[str]]:
    """Run the examples in `folder` (stops at the first failure); return those run."""
    hitogata = [sys.executable, "-m", "hitogata.cli"]
    done, missing = [], set()  # outputs of skipped examples: a later one reading them is skipped too
    for argv in examples():
        words = {w.rstrip("/") for w in argv}
        if (len(argv) > 1 and argv[1] in skip) or words & missing:
            if "--out" in argv:
                missing.add(argv[argv.index("--out") + 1].rstrip("/"))
            continue
        subprocess.run([*hitogata, *argv[1:]], cwd=folder, check=True, env=os.environ.copy(),
                       stdout=subprocess.DEVNULL)
        done.append(argv)
    return done


if __name__ == "__main__":
    target = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="hitogata-readme-"))
    for argv in run(target):
        print("ok:", shlex.join(argv))
    print(f"all README examples ran in {target}")
