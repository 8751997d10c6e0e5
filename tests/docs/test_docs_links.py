"""Every link in the docs leads somewhere: relative Markdown links in README.md, CHANGELOG.md,
examples/README.md and docs/ resolve to files of the repository, and every `docs/….md` path the docs, the examples or
the source's docstrings name exists — so a page moved or renamed is caught, not left to a reader."""

from __future__ import annotations

import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
LINK = re.compile(r"\]\(([^)\s]+)\)")
DOC_PATH = re.compile(r"\bdocs/[\w./-]+\.md\b")


def markdown_files() -> list[Path]:
    return [REPO / "README.md", REPO / "CHANGELOG.md", REPO / "examples" / "README.md",
            *sorted((REPO / "docs").rglob("*.md"))]


def test_relative_links_resolve():
    broken = []
    for page in markdown_files():
        for target in LINK.findall(page.read_text(encoding="utf-8")):
            if re.match(r"[a-z]+:", target) or target.startswith("#"):
                continue  # a web address or an anchor on the same page
            path = (page.parent / target.split("#")[0]).resolve()
            if not path.exists():
                broken.append(f"{page.relative_to(REPO)}: {target}")
    assert not broken, "\n".join(broken)


def test_named_doc_pages_exist():
    texts = [*markdown_files(), *sorted((REPO / "src").rglob("*.py")), *sorted((REPO / "examples").glob("*.py"))]
    missing = sorted({f"{path.relative_to(REPO)}: {name}" for path in texts
                      for name in DOC_PATH.findall(path.read_text(encoding="utf-8"))
                      if not (REPO / name).is_file() and not (path.parent / name).is_file()})
    assert not missing, "\n".join(missing)
