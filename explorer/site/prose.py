"""Lesson prose (:mod:`explorer.lessons.text` blocks) as HTML: paragraphs, lists, tables,
inline and display math as MathML, live numbers baked with their tooltips, ``{{try:K}}``
as a link to the step's K-th try-this, figures and formulas where their markers stand."""

from __future__ import annotations

import html
import re
from typing import Callable

from explorer import derived
from explorer.lessons import text as lesson_text
from explorer.site.mathml import to_mathml
from explorer.site.values import Baker

_TAGS = {"bold": ("<strong>", "</strong>"), "italic": ("<em>", "</em>"),
         "bold-italic": ("<strong><em>", "</em></strong>"), "code": ("<code>", "</code>"),
         "regular": ("", "")}
_TOKEN = "LIVEVALUE{}X"
_TOKEN_MTEXT = re.compile(r"<mtext>LIVEVALUE(\d+)X</mtext>")

FigureHtml = Callable[[str], str]
"""figure id -> the figure's HTML (the page writer's)."""
TryHtml = Callable[[int], str]
"""try-this index (1-based) -> the inline link to it."""


def math(latex: str, baker: Baker, display: bool = False) -> str:
    """``latex`` (which may quote live numbers) as MathML, each number an ``<mn>`` with
    its tooltip. The numbers go in as placeholders the converter keeps as ``<mtext>``,
    so a number never changes how the formula around it is read."""
    numbers: list[tuple[str, str]] = []

    def placeholder(name: str, fmt: str) -> str:
        numbers.append((name, fmt))
        return r"\text{" + _TOKEN.format(len(numbers) - 1) + "}"

    markup = to_mathml(lesson_text.substitute(latex, placeholder), display)
    shown = {i: baker.mn(name, fmt) for i, (name, fmt) in enumerate(numbers)}
    markup = _TOKEN_MTEXT.sub(lambda m: shown[int(m.group(1))], markup)
    # the annotation keeps the lesson's source with the numbers filled in as text
    return re.sub(_TOKEN.format(r"(\d+)"), lambda m: html.escape(
        baker.baked[len(baker.baked) - len(numbers) + int(m.group(1))][2]), markup)


def runs(items: tuple, baker: Baker, try_link: TryHtml | None = None) -> str:
    out = []
    for run in items:
        if isinstance(run, lesson_text.Text):
            start, end = _TAGS[run.style]
            out.append(f"{start}{html.escape(run.text)}{end}")
        elif isinstance(run, lesson_text.Math):
            out.append(math(run.latex, baker))
        elif isinstance(run, lesson_text.Value):
            start, end = _TAGS[run.style]
            out.append(f"{start}{baker.span(run.name, run.format)}{end}")
        elif isinstance(run, lesson_text.TryButton):
            out.append(try_link(run.index) if try_link else "")
    return "".join(out)


def formula(name: str, baker: Baker) -> str:
    """A derivation result typeset as display math, its statement under it."""
    result = derived.get(name)
    return (f'<div class="formula" title="{html.escape(result.tooltip)}">'
            f"{math(result.latex, baker, display=True)}"
            f'<p class="formula-note">{html.escape(result.statement)} '
            f"<code>{html.escape(result.name)}</code></p></div>")


def blocks(text: str, baker: Baker, figure: FigureHtml | None = None,
           try_link: TryHtml | None = None) -> str:
    """The HTML of a step's ``text``."""
    out: list[str] = []
    open_list: str | None = None
    for block in lesson_text.parse(text):
        kind = None
        if isinstance(block, lesson_text.Item):
            kind = "ul" if block.marker == "•" else "ol"
        if open_list and kind != open_list:
            out.append(f"</{open_list}>")
            open_list = None
        if kind and not open_list:
            out.append(f"<{kind}>")
            open_list = kind
        if isinstance(block, lesson_text.Paragraph):
            out.append(f"<p>{runs(block.runs, baker, try_link)}</p>")
        elif isinstance(block, lesson_text.Item):
            out.append(f"<li>{runs(block.runs, baker, try_link)}</li>")
        elif isinstance(block, lesson_text.DisplayMath):
            out.append(f'<div class="display-math">{math(block.latex, baker, True)}</div>')
        elif isinstance(block, lesson_text.Table):
            out.append(_table(block, baker, try_link))
        elif isinstance(block, lesson_text.FigureRef):
            out.append(figure(block.id) if figure else "")
        elif isinstance(block, lesson_text.FormulaRef):
            out.append(formula(block.name, baker))
    if open_list:
        out.append(f"</{open_list}>")
    return "\n".join(out)


def inline(text: str, baker: Baker) -> str:
    """One paragraph of text (a prompt, a caption) as inline HTML, without ``<p>``."""
    parsed = lesson_text.parse(text)
    return " ".join(runs(block.runs, baker) for block in parsed
                    if isinstance(block, (lesson_text.Paragraph, lesson_text.Item)))


def _table(table: lesson_text.Table, baker: Baker, try_link: TryHtml | None) -> str:
    head = "".join(f"<th>{runs(cell, baker, try_link)}</th>" for cell in table.header)
    body = "".join("<tr>" + "".join(f"<td>{runs(cell, baker, try_link)}</td>" for cell in row)
                   + "</tr>" for row in table.rows)
    return (f'<div class="table-wrap"><table><thead><tr>{head}</tr></thead>'
            f"<tbody>{body}</tbody></table></div>")
