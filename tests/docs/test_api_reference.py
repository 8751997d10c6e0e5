"""docs/reference/api.md is what tools/api_reference.py writes from today's docstrings: the API
reference never goes stale (change a public docstring, run the tool, commit both)."""

from __future__ import annotations

import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "tools"))
import api_reference  # noqa: E402


def test_the_committed_api_reference_is_what_the_tool_writes():
    committed = api_reference.OUT.read_text(encoding="utf-8")
    assert committed == api_reference.render(), "docs/reference/api.md is stale: run python tools/api_reference.py"


def test_every_public_name_has_a_section_with_its_docstring():
    import hitogata

    text = api_reference.OUT.read_text(encoding="utf-8")
    for name in hitogata.__all__:
        assert f"## `{name}`" in text, name
    assert hitogata.pose_body.__doc__.splitlines()[0].strip() in text
    assert "(no docstring)" not in text, "every public name says what it is"
