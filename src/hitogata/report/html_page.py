"""A self-contained HTML page: tables, images as data URIs, inline style, no script, nothing fetched.

The page opens offline from a file: every picture is embedded (base64 PNG),
the style is inline, there is no JavaScript, no web font and no link to
another resource (the icon is an empty data URI, so a browser asks for no
favicon). Every text is HTML-escaped here.
"""

from __future__ import annotations

import base64
from collections.abc import Sequence
from html import escape

STYLE = """
body { font-family: sans-serif; margin: 0 auto; max-width: 1200px; padding: 0 1.5em 3em; color: #222; }
h1 { margin-bottom: 0.2em; } h2 { border-bottom: 2px solid #ccc; margin-top: 2em; } h3 { margin-top: 1.5em; }
nav { background: #f4f4f4; padding: 0.5em 1em; } nav a { margin-right: 1em; }
table { border-collapse: collapse; margin: 0.6em 0; font-size: 0.9em; }
th, td { border: 1px solid #ccc; padding: 0.2em 0.6em; } td.n { text-align: right; font-variant-numeric: tabular-nums; }
th { background: #eee; } caption { text-align: left; font-weight: bold; padding: 0.3em 0; }
img { max-width: 100%; display: block; margin: 0.6em 0; }
.summary { background: #fff7e0; border-left: 4px solid #e0a800; padding: 0.6em 1em; }
.swatch { display: inline-block; width: 0.9em; height: 0.9em; margin-right: 0.4em; vertical-align: middle; }
.note { color: #555; font-size: 0.9em; }
"""


class Cell(str):
    """A table cell that is already HTML (not escaped again)."""


def cell(value: object) -> str:
    """A <td>: numbers right-aligned (the text given is shown as is)."""
    if isinstance(value, Cell):
        return f"<td>{value}</td>"
    text = escape(str(value))
    numeric = text.lstrip("+-−").replace(".", "", 1).replace(" %", "").isdigit()
    return f'<td class="n">{text}</td>' if numeric else f"<td>{text}</td>"


def table(columns: Sequence[str], rows: Sequence[Sequence[object]], id: str = "", caption: str = "") -> str:
    """An HTML table with a header row; `id` for anchors and tests."""
    head = "".join(f"<th>{escape(c)}</th>" for c in columns)
    body = "".join("<tr>" + "".join(cell(v) for v in row) + "</tr>" for row in rows)
    ident = f' id="{escape(id)}"' if id else ""
    title = f"<caption>{escape(caption)}</caption>" if caption else ""
    return f"<table{ident}>{title}<thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def image(png: bytes, alt: str) -> str:
    """An <img> holding the PNG as a data URI."""
    return f'<img alt="{escape(alt)}" src="data:image/png;base64,{base64.b64encode(png).decode("ascii")}">'


def paragraph(text: str, css: str = "") -> str:
    return f'<p class="{escape(css)}">{escape(text)}</p>' if css else f"<p>{escape(text)}</p>"


def swatch(colour: str, text: str) -> Cell:
    """A table cell's text after a small square of `colour`."""
    return Cell(f'<span class="swatch" style="background:{escape(colour)}"></span>{escape(text)}')


def section(id: str, title: str, parts: Sequence[str], level: int = 2) -> str:
    """A titled block of HTML parts."""
    return f'<section id="{escape(id)}"><h{level}>{escape(title)}</h{level}>{"".join(parts)}</section>'


def page(title: str, intro: Sequence[str], sections: Sequence[tuple[str, str, str]]) -> str:
    """The whole document: title, intro parts, a contents line, then each (id, title, html) section."""
    nav = "".join(f'<a href="#{escape(i)}">{escape(t)}</a>' for i, t, _ in sections)
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            '<meta name="viewport" content="width=device-width, initial-scale=1">'
            f'<link rel="icon" href="data:,"><title>{escape(title)}</title><style>{STYLE}</style></head>'
            f"<body><h1>{escape(title)}</h1>{''.join(intro)}<nav>{nav}</nav>"
            f"{''.join(html for _, _, html in sections)}</body></html>\n")
