"""The docs speak of the project, not of how it was built: no diary in the user docs, the README or
the source's docstrings and comments.

A numbered or dated round of work ("session 12", "round 3", "wave 2", "2026-11-24"), the history of
attempts ("tried and left", "what moved") or an issue number ("issue 12", "#12") belongs in the
version history, not in text a user or a maintainer reads to learn what the code does. Design
decisions with their numbers live in docs/decisions/, user-visible changes in CHANGELOG.md.
"""

from __future__ import annotations

import ast
import io
import re
import tokenize
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

DIARY = {
    "a numbered round of work": r"\b(?:sessions?|rounds?|waves?|sprints?|iterations? of work)\s+\d+\b",
    "a round of work": r"\b(?:this|that|last|previous|earlier|next|another)\s+(?:session|wave|sprint)s?\b"
                       r"|\b(?:this|earlier|previous)\s+rounds?\b|\bthe\s+(?:session|round)\s+before\b",
    "a dated entry": r"\b20\d\d-[01]\d-[0-3]\d\b"
                     r"|\b(?:Jan|Feb|Mar|Apr|May|Jun|Jul|Aug|Sep|Oct|Nov|Dec)[a-z]*\.? \d{1,2},? 20\d\d\b"
                     r"|\b\d{1,2} (?:Jan|Feb|Mar|Apr|May|Jun|Jul|Aug|Sep|Oct|Nov|Dec)[a-z]* 20\d\d\b",
    "a commit of the history": r"\b(?:commit|at|against|before|since)\s+(?=[0-9a-f]*\d)(?=[0-9a-f]*[a-f])[0-9a-f]{7,40}\b",
    "the history of attempts": r"\btried\s+and\s+(?:left|rejected|dropped)\b|\bwhat\s+moved\b|\btried\s+this\s+"
                               r"(?:session|round)\b|\btried\s+on\s+the\s+way\b",
    "an issue number": r"\b(?:issues?|pull\s+requests?|PRs?|tickets?)\s+#?\d+\b|(?<![\w&#/\"'=-])#\d{1,5}\b(?![\w-])",
}
PATTERNS = {what: re.compile(pattern, re.IGNORECASE) for what, pattern in DIARY.items()}


def diary(text: str) -> list[tuple[str, str]]:
    """(what, the words) for every diary phrase in `text`."""
    return [(what, m.group(0)) for what, pattern in PATTERNS.items() for m in pattern.finditer(text)]


def markdown_files() -> list[Path]:
    return [REPO / "README.md", *sorted((REPO / "docs").rglob("*.md"))]


def python_prose(path: Path) -> list[tuple[int, str]]:
    """(line, text) of every docstring and comment of a Python file."""
    source = path.read_text(encoding="utf-8")
    found = [(tok.start[0], tok.string) for tok in tokenize.generate_tokens(io.StringIO(source).readline)
             if tok.type == tokenize.COMMENT]
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            doc = ast.get_docstring(node, clean=False)
            if doc:
                found.append((node.body[0].lineno, doc))
    return found


def test_the_patterns_find_diary_and_leave_prose_alone():
    for text in ("session 12's run", "measured in round 3", "wave 2 of the work", "rerun 2026-11-23",
                 "Tried and left: a graded lattice", "What moved. The skin", "before issue 15",
                 "the measurements of issue 15", "fixed in #12", "(#7)", "this session, after its changes",
                 "the round before", "the run before this session", "measured 24 November 2026",
                 "on Nov 24, 2026", "against eabcd71 in the same run", "c7f1e03's solver at commit c7f1e03"):
        assert diary(text), text
    for text in ("shear-wave elastography", "in rounds until nothing changes", "at most 3 rounds",
                 "colour #1b7837", "ISO 8559-1:2017", "## Headings", "the 2 × 2 FᵀF",
                 "a round trip through BVH", "Session cookies",
                 "Gordon et al. 2014", "ISO 2631-1:1997", "sha256 at 0x1f", "against 1e-12"):
        assert not diary(text), text


@pytest.mark.parametrize("path", markdown_files(), ids=lambda p: str(p.relative_to(REPO)))
def test_user_docs_have_no_diary(path: Path):
    found = [f"{path.relative_to(REPO)}:{text[:m.start()].count(chr(10)) + 1}: {what}: {m.group(0)!r}"
             for text in [path.read_text(encoding="utf-8")]
             for what, pattern in PATTERNS.items() for m in pattern.finditer(text)]
    assert not found, "\n".join(found)


def diary_in_python(paths: list[Path]) -> list[str]:
    """'file:line: what: words' for every diary phrase in the docstrings and comments of `paths`."""
    return [f"{path.relative_to(REPO)}:{line}: {what}: {words!r}"
            for path in paths for line, text in python_prose(path) for what, words in diary(text)]


def test_docstrings_and_comments_under_src_have_no_diary():
    found = diary_in_python(sorted((REPO / "src").rglob("*.py")))
    assert not found, "\n".join(found)


def test_examples_have_no_diary():
    found = diary_in_python(sorted((REPO / "examples").glob("*.py")))
    assert not found, "\n".join(found)
