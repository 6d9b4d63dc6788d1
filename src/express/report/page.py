"""One self-contained HTML page: sections of text, tables, inline SVG figures and MathML.

Nothing on the page is fetched: figures are inline SVG (Matplotlib's SVG backend with a
fixed hash salt and no date, so the same model gives the same page), mathematics is
MathML (rendered natively by current browsers), the style sheet is inline.  Every text
that comes from a model file is escaped.
"""

from __future__ import annotations

import html
import io
import re
from collections.abc import Sequence
from dataclasses import dataclass, field

__all__ = ["Figure", "Math", "Section", "Table", "render_page", "svg_of"]

_STYLE = """
body { font-family: system-ui, sans-serif; max-width: 72rem; margin: 1rem auto; padding: 0 1rem; color: #222; }
h1 { font-size: 1.5rem; } h2 { font-size: 1.2rem; border-bottom: 1px solid #ccc; margin-top: 2rem; }
table { border-collapse: collapse; font-size: 0.85rem; margin: 0.5rem 0; }
th, td { border: 1px solid #ddd; padding: 0.2rem 0.5rem; text-align: left; vertical-align: top; }
th { background: #f4f4f4; } td.number { text-align: right; font-variant-numeric: tabular-nums; }
figure { margin: 0.5rem 0; } figure svg { max-width: 100%; height: auto; }
figcaption { font-size: 0.85rem; color: #555; }
math { font-size: 1.1rem; } p.note { font-size: 0.85rem; color: #555; }
div.scroll { overflow: auto; max-width: 100%; } div.equations { max-height: 36rem; border: 1px solid #eee; }
code { font-family: ui-monospace, monospace; font-size: 0.9em; background: #f4f4f4; padding: 0 0.2em; }
"""


@dataclass(frozen=True)
class Table:
    """A table: ``header`` and ``rows`` of cells (text; numbers are right-aligned)."""

    header: Sequence[str]
    rows: Sequence[Sequence[object]]
    caption: str = ""


@dataclass(frozen=True)
class Figure:
    """An inline SVG figure (``svg`` is the SVG text) with a caption."""

    svg: str
    caption: str


@dataclass(frozen=True)
class Math:
    """A list of MathML equations (``label``, MathML ``<math>`` content)."""

    equations: Sequence[tuple[str, str]]


@dataclass(frozen=True)
class Section:
    """A titled section: paragraphs, tables, figures and mathematics, in order."""

    title: str
    parts: Sequence[str | Table | Figure | Math] = field(default_factory=tuple)


def svg_of(figure) -> str:
    """The SVG text of a Matplotlib figure, deterministic, without the XML prologue."""
    import matplotlib

    buffer = io.StringIO()
    with matplotlib.rc_context({"svg.hashsalt": "express-report", "svg.fonttype": "none"}):
        figure.savefig(buffer, format="svg", metadata={"Date": None})
    text = buffer.getvalue()
    return text[text.index("<svg"):]


def _cell(value: object) -> str:
    if isinstance(value, float):
        return f'<td class="number">{value:.6g}</td>'
    if isinstance(value, int) and not isinstance(value, bool):
        return f'<td class="number">{value}</td>'
    return f"<td>{html.escape(str(value))}</td>"


def _table(table: Table) -> str:
    head = "".join(f"<th>{html.escape(h)}</th>" for h in table.header)
    body = "\n".join("<tr>" + "".join(_cell(c) for c in row) + "</tr>" for row in table.rows)
    caption = f"<caption>{html.escape(table.caption)}</caption>" if table.caption else ""
    return (f'<div class="scroll"><table>{caption}<thead><tr>{head}</tr></thead>\n<tbody>\n{body}\n</tbody>'
            "</table></div>")


def _part(part: str | Table | Figure | Math) -> str:
    if isinstance(part, Table):
        return _table(part)
    if isinstance(part, Figure):
        return f"<figure>{part.svg}<figcaption>{_text(part.caption)}</figcaption></figure>"
    if isinstance(part, Math):
        rows = "\n".join(
            f'<tr><td>{html.escape(label)}</td><td><math display="block">{mathml}</math></td></tr>'
            for label, mathml in part.equations
        )
        return f'<div class="scroll equations"><table><tbody>\n{rows}\n</tbody></table></div>'
    return f"<p>{_text(part)}</p>"


def _text(text: str) -> str:
    """Escaped text with ``code`` spans (Markdown backticks) as ``<code>``: no literal
    Markdown on the page."""
    return re.sub(r"`([^`]+)`", r"<code>\1</code>", html.escape(text))


def render_page(title: str, sections: Sequence[Section], *, note: str = "") -> str:
    """The whole HTML document."""
    body = []
    for section in sections:
        anchor = html.escape(section.title.lower().replace(" ", "-"))
        body.append(f'<section id="{anchor}"><h2>{html.escape(section.title)}</h2>')
        body.extend(_part(part) for part in section.parts)
        body.append("</section>")
    contents = "".join(
        f'<li><a href="#{html.escape(s.title.lower().replace(" ", "-"))}">{html.escape(s.title)}</a></li>' for s in sections
    )
    return (
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
        f"<title>{html.escape(title)}</title>\n<style>{_STYLE}</style>\n</head>\n<body>\n"
        f"<h1>{html.escape(title)}</h1>\n"
        + (f'<p class="note">{_text(note)}</p>\n' if note else "")
        + f"<nav><ol>{contents}</ol></nav>\n"
        + "\n".join(body)
        + "\n</body>\n</html>\n"
    )
