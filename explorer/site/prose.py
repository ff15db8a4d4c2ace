"""Lesson prose (:mod:`explorer.lessons.text` blocks, the site's side of every variant)
as HTML: paragraphs, lists, tables, inline and display math as MathML, live numbers baked
with their tooltips, ``{{try:K}}`` as a link to the step's K-th try-this, ``{{fig:ID}}``
as a link to the figure by its number, figures and formulas where their markers stand,
and the glossary's terms as links to their definitions (a popover with the script)."""

from __future__ import annotations

import html
import re
from collections.abc import Callable

from explorer import derived
from explorer.lessons import glossary as lesson_glossary
from explorer.lessons import text as lesson_text
from explorer.site.controls import attribute
from explorer.site.mathml import to_mathml
from explorer.site.values import Baker, plain_words

_TAGS = {"bold": ("<strong>", "</strong>"), "italic": ("<em>", "</em>"),
         "bold-italic": ("<strong><em>", "</em></strong>"), "code": ("<code>", "</code>"),
         "regular": ("", "")}
_TOKEN = "LIVEVALUE{}X"
_TOKEN_MTEXT = re.compile(r"<mtext>LIVEVALUE(\d+)X</mtext>")

FigureHtml = Callable[[str], str]
"""figure id -> the figure's HTML (the page writer's)."""
TryHtml = Callable[[int], str]
"""try-this index (1-based) -> the inline link to it."""
FigureNumbers = dict[str, int]
"""figure id of the step (``view``: its picture) -> its number on the page."""
MEDIUM = "web"


class Terms:
    """The glossary's terms in a page's prose: the first use of each term in a step
    becomes a link to its definition at the end of the page (:meth:`used` lists them)."""

    def __init__(self, terms: tuple[lesson_glossary.Term, ...]) -> None:
        self.terms = terms
        self.anchors: dict[str, str] = {}
        self.in_step: set[str] = set()

    def new_step(self) -> None:
        self.in_step = set()

    def anchor(self, term: lesson_glossary.Term) -> str:
        if term.term not in self.anchors:
            self.anchors[term.term] = "term-" + re.sub(r"[^a-z0-9]+", "-", term.term.lower()
                                                       ).strip("-")
        return self.anchors[term.term]

    def used(self) -> list[tuple[str, str, str]]:
        """(anchor, term, meaning) of every term linked on the page, in glossary order."""
        return [(self.anchors[t.term], t.term, t.meaning) for t in self.terms
                if t.term in self.anchors]

    def mark(self, text: str) -> str:
        """``text`` as HTML with the step's first use of each term linked."""
        tokens = re.split(r"(\s+)", text)
        words = tokens[0::2]
        out = [html.escape(token) for token in tokens]
        for first, count, term in lesson_glossary.matches(words, self.terms):
            if term.term in self.in_step:
                continue
            self.in_step.add(term.term)
            start, end = 2 * first, 2 * (first + count - 1)
            head, tail = tokens[start], tokens[end]
            lead = head[:len(head) - len(head.lstrip(lesson_glossary.PUNCTUATION))]
            trail = tail[len(tail.rstrip(lesson_glossary.PUNCTUATION)):]
            inner = "".join(tokens[start:end + 1])
            inner = inner[len(lead):len(inner) - len(trail) if trail else None]
            anchor = self.anchor(term)
            out[start] = (f'{html.escape(lead)}<a class="term" {attribute("term")} '
                          f'href="#{anchor}" aria-describedby="{anchor}-def">'
                          f"{html.escape(inner)}</a>{html.escape(trail)}")
            for index in range(start + 1, end + 1):
                out[index] = ""
        return "".join(out)


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


def figure_link(number: int) -> str:
    return f'<a class="fig-ref" href="#fig-{number}">Figure {number}</a>'


def runs(items: tuple, baker: Baker, try_link: TryHtml | None = None,
         numbers: FigureNumbers | None = None, terms: Terms | None = None) -> str:
    out = []
    for run in items:
        if isinstance(run, lesson_text.Text):
            start, end = _TAGS[run.style]
            words = (terms.mark(run.text) if terms is not None and run.style != "code"
                     else html.escape(run.text))
            out.append(f"{start}{words}{end}")
        elif isinstance(run, lesson_text.FigureNumber):
            number = (numbers or {}).get(run.id)
            if number is None:
                raise ValueError(f"{{{{fig:{run.id}}}}}: no such figure on the page")
            out.append(figure_link(number))
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
    return (f'<div class="formula">'
            f'<div class="display-math">{math(result.latex, baker, display=True)}</div>'
            f'<p class="formula-note">{html.escape(plain_words(result.statement))}</p></div>')


def blocks(text: str, baker: Baker, figure: FigureHtml | None = None,
           try_link: TryHtml | None = None, numbers: FigureNumbers | None = None,
           terms: Terms | None = None) -> str:
    """The HTML of a step's ``text`` (its site side)."""
    out: list[str] = []
    open_list: str | None = None

    def words(items: tuple) -> str:
        return runs(items, baker, try_link, numbers, terms)

    for block in lesson_text.parse(text, MEDIUM):
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
            out.append(f"<p>{words(block.runs)}</p>")
        elif isinstance(block, lesson_text.Item):
            out.append(f"<li>{words(block.runs)}</li>")
        elif isinstance(block, lesson_text.DisplayMath):
            out.append(f'<div class="display-math">{math(block.latex, baker, True)}</div>')
        elif isinstance(block, lesson_text.Table):
            out.append(_table(block, words))
        elif isinstance(block, lesson_text.FigureRef):
            out.append(figure(block.id) if figure else "")
        elif isinstance(block, lesson_text.FormulaRef):
            out.append(formula(block.name, baker))
    if open_list:
        out.append(f"</{open_list}>")
    return "\n".join(out)


def inline(text: str, baker: Baker, numbers: FigureNumbers | None = None) -> str:
    """One paragraph of text (a prompt, a caption) as inline HTML, without ``<p>``."""
    parsed = lesson_text.parse(text, MEDIUM)
    return " ".join(runs(block.runs, baker, None, numbers) for block in parsed
                    if isinstance(block, (lesson_text.Paragraph, lesson_text.Item)))


def _table(table: lesson_text.Table, words: Callable[[tuple], str]) -> str:
    head = "".join(f'<th scope="col">{words(cell)}</th>' for cell in table.header)
    body = "".join("<tr>" + "".join(f"<td>{words(cell)}</td>" for cell in row)
                   + "</tr>" for row in table.rows)
    return (f'<div class="table-wrap"><table><thead><tr>{head}</tr></thead>'
            f"<tbody>{body}</tbody></table></div>")
