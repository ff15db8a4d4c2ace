r"""Lesson prose as data: blocks of styled runs, parsed once, drawn by the article view.

A lesson step's ``text`` is a small markdown dialect, chosen so that every piece has one
meaning the window can lay out itself (``explorer/ui/textflow.py``) and the tests can
check without a window:

* paragraphs separated by a blank line; ``* `` / ``- `` bullets and ``1. `` numbered items;
* tables: lines that start with ``|``, the first row the header, a ``|---|`` line under it;
* ``**bold**``, ``*italic*``, ```code```;
* ``$...$`` inline math and ``$$...$$`` display math (LaTeX, typeset by MicroTeX; a
  display formula states its left-hand side);
* ``{{name}}`` or ``{{name:format}}``: a live number (:mod:`explorer.lessons.live_values`), also
  inside math, e.g. ``$c_0 = {{derived.sh.c0:.6f}}$``;
* markers: ``{{figure:ID}}`` (a figure of the step) and ``{{formula:NAME}}`` (a
  derivation result typeset as display math) stand between paragraphs (one inside a
  paragraph splits it there); ``{{try:K}}`` is the step's K-th try-this as a button in
  the line.
* variants: ``{{window}}A{{web}}B{{end}}`` reads A in the explorer window and B on the
  course site (``{{web}}B{{end}}``: on the site only, ``{{window}}A{{end}}``: in the window
  only). Either side may hold anything a step's text holds, paragraphs included; variants
  do not nest. A sentence that tells the reader to press, drag or open a panel of the
  window says on the site what to look at instead (``explorer/site/controls.py`` lists
  the controls a page has).
* ``{{fig:ID}}``: the step's figure ID (``view``: the step's picture) by its number on
  the site ("Figure 3", a link), "the figure" ("the main view") in the window; mostly
  used on the site's side of a variant.

Examples
--------
>>> blocks = parse("Flux $\\Phi$ is **{{audit.injected:.3f}}** W.")
>>> [type(run).__name__ for run in blocks[0].runs]
['Text', 'Math', 'Text', 'Value', 'Text']
>>> blocks[0].runs[3]
Value(name='audit.injected', format='.3f', style='bold')
>>> for_medium("Open {{window}}the Inspect panel{{web}}the picture below{{end}}.", "web")
'Open the picture below.'
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import lru_cache

STYLES = ("regular", "bold", "italic", "bold-italic", "code")
VARIANT_MARKERS = ("window", "web", "end")
"""``{{window}}``, ``{{web}}`` and ``{{end}}``: the two sides of a variant."""
MARKERS = ("figure", "formula", "try", "fig", *VARIANT_MARKERS)
"""Names that make ``{{name:argument}}`` a marker rather than a live number."""
MEDIA = ("window", "web")
"""Where a text is read: the explorer window or the course site."""
BLOCK_MARKERS = ("figure", "formula")


@dataclass(frozen=True)
class Text:
    text: str
    style: str = "regular"


@dataclass(frozen=True)
class Math:
    latex: str
    """LaTeX without the dollars; may hold ``{{...}}`` live numbers."""


@dataclass(frozen=True)
class Value:
    """A live number: the quantity ``name`` formatted with ``format``."""

    name: str
    format: str = ""
    style: str = "regular"


@dataclass(frozen=True)
class TryButton:
    index: int
    """1-based index into the step's try-this list."""


@dataclass(frozen=True)
class FigureNumber:
    """A reference to one of the step's figures by its number on the page."""

    id: str
    """A figure id of the step, or ``view`` (the step's picture)."""


Run = Text | Math | Value | TryButton | FigureNumber


@dataclass(frozen=True)
class Paragraph:
    runs: tuple[Run, ...]


@dataclass(frozen=True)
class Item:
    """A list item: ``marker`` is "•" or "3."."""

    runs: tuple[Run, ...]
    marker: str


@dataclass(frozen=True)
class DisplayMath:
    latex: str


@dataclass(frozen=True)
class Table:
    """``header`` and ``rows``: each a tuple of cells, each cell a tuple of runs."""

    header: tuple[tuple[Run, ...], ...]
    rows: tuple[tuple[tuple[Run, ...], ...], ...]


@dataclass(frozen=True)
class FigureRef:
    id: str


@dataclass(frozen=True)
class FormulaRef:
    name: str


Block = Paragraph | Item | DisplayMath | Table | FigureRef | FormulaRef
PARSED_KEPT = 1024
"""Texts whose blocks :func:`parse` keeps (a course's steps and prompts: a few hundred)."""

_FIELD = re.compile(r"\{\{\s*([^{}:\s]+)\s*(?::([^{}]*))?\}\}")
_ITEM = re.compile(r"^(?:([*-])|(\d+)\.)\s+(.*)$")
_DISPLAY = re.compile(r"\$\$(.+?)\$\$", re.S)
MARKER_FIELD = re.compile(r"\{\{\s*(figure|formula|try|fig)\s*:\s*([^{}\s]+)\s*\}\}")
_FIG = re.compile(r"\{\{\s*fig\s*:\s*([^{}\s]+)\s*\}\}")
_BLOCK_MARKER = re.compile(r"\{\{\s*(figure|formula)\s*:\s*([^{}\s]+)\s*\}\}")


class TextError(ValueError):
    """Prose the parser cannot read (an unclosed ``$``, ``**`` or ``{{``)."""


def fields(text: str) -> list[tuple[str, str]]:
    """Every ``{{name:argument}}`` in ``text`` (markers and live numbers, math included),
    as (name, argument) pairs in order; the argument is "" when absent."""
    return [(m.group(1), (m.group(2) or "").strip()) for m in _FIELD.finditer(text)]


def placeholders(text: str) -> list[tuple[str, str]]:
    """The live numbers of ``text``: (quantity name, format) pairs."""
    return [(name, fmt) for name, fmt in fields(text) if name not in MARKERS]


_VARIANT = re.compile(r"\{\{\s*(window|web)\s*\}\}(.*?)(?:\{\{\s*web\s*\}\}(.*?))?"
                      r"\{\{\s*end\s*\}\}", re.S)
_VARIANT_LEFT = re.compile(r"\{\{\s*(window|web|end)\s*\}\}")


def for_medium(text: str, medium: str = "window") -> str:
    """``text`` as read in ``medium`` ("window" or "web"): each variant replaced by its
    side for that medium. :class:`TextError` for a variant that is not closed, nested, or
    has two ``{{web}}`` sides."""
    if medium not in MEDIA:
        raise ValueError(f"medium must be one of {MEDIA}, got {medium!r}")

    def side(match: re.Match) -> str:
        first, body, web = match.group(1), match.group(2), match.group(3)
        if (first == "web" and web is not None) or _VARIANT_LEFT.search(body + (web or "")):
            raise TextError(f"a variant has two {{{{web}}}} sides or a variant inside: "
                            f"{match.group(0)[:60]!r}")
        if first == "web":
            return body if medium == "web" else ""
        return (web or "") if medium == "web" else body

    chosen = _VARIANT.sub(side, text)
    if medium == "window":      # the window numbers no figures: it says which one in words
        chosen = _FIG.sub(lambda m: "the main view" if m.group(1) == "view" else "the figure",
                          chosen)
    left = _VARIANT_LEFT.search(chosen)
    if left is not None:
        near = chosen[max(left.start() - 30, 0):][:60]
        raise TextError(f"{left.group(0)} without its variant: write {{{{window}}}}A"
                        f"{{{{web}}}}B{{{{end}}}} (near {near!r})")
    return chosen


@lru_cache(maxsize=PARSED_KEPT)
def parse(text: str, medium: str = "window") -> tuple[Block, ...]:
    """The blocks of ``text`` as read in ``medium`` (see the module docstring);
    :class:`TextError` for unbalanced delimiters. Kept by text and medium (the blocks
    are frozen): the window parses a step's text and its try-this prompts every frame."""
    blocks: list[Block] = []
    for chunk in _chunks(for_medium(text, medium)):
        if chunk[0] == "table":
            blocks.append(_table(chunk[1]))
            continue
        if chunk[0] == "item":
            _, marker, body = chunk
            pieces = _split_blocks(body)
            if pieces and isinstance(pieces[0], Paragraph):   # the item's own text
                pieces[0] = Item(pieces[0].runs, marker)
            blocks.extend(pieces)
            continue
        for piece in _split_blocks(chunk[1]):
            blocks.append(piece)
    return tuple(blocks)


def _chunks(text: str) -> list[tuple]:
    """("para", text) and ("item", marker, text) pieces; hard line breaks joined, a
    display formula kept whole even across blank lines."""
    chunks: list[tuple] = []
    current: list[str] = []
    marker: str | None = None
    in_display = False

    def flush() -> None:
        nonlocal marker
        if current:
            body = " ".join(line.strip() for line in current).strip()
            if body:
                chunks.append(("item", marker, body) if marker else ("para", body))
        current.clear()
        marker = None

    table: list[str] = []
    for line in text.strip().splitlines():
        stripped = line.strip()
        if table and not stripped.startswith("|"):
            chunks.append(("table", list(table)))
            table.clear()
        if not in_display and stripped.startswith("|"):
            flush()
            table.append(stripped)
            continue
        if in_display:
            current.append(stripped)
            if stripped.count("$$") % 2:
                in_display = False
            continue
        if not stripped:
            flush()
            continue
        match = _ITEM.match(stripped)
        if match and not stripped.startswith("**"):
            flush()
            marker = "•" if match.group(1) else f"{match.group(2)}."
            stripped = match.group(3)
        current.append(stripped)
        if stripped.count("$$") % 2:
            in_display = True
    if in_display:
        raise TextError("a $$ display formula is not closed")
    flush()
    if table:
        chunks.append(("table", table))
    return chunks


_RULE = re.compile(r"^\|?\s*:?-{3,}:?\s*(\|\s*:?-{3,}:?\s*)*\|?$")


def _table(lines: list[str]) -> Table:
    """A pipe table: the header row, a ``|---|---|`` rule, the body rows."""
    if len(lines) < 2 or not _RULE.match(lines[1]):
        raise TextError(f"a table needs a header row and a |---| rule under it: {lines[0]!r}")

    def cells(line: str) -> list[str]:
        body = line.strip()
        if body.startswith("|"):
            body = body[1:]
        if body.endswith("|"):
            body = body[:-1]
        return [cell.strip() for cell in body.split("|")]

    header = cells(lines[0])
    rows = []
    for line in lines[2:]:
        row = cells(line)
        if len(row) != len(header):
            raise TextError(f"a table row has {len(row)} cells, the header {len(header)}: "
                            f"{line!r}")
        rows.append(tuple(_runs(cell) for cell in row))
    return Table(tuple(_runs(cell) for cell in header), tuple(rows))


def _split_blocks(body: str) -> list[Block]:
    """A paragraph, split where it holds display math or block markers."""
    out: list[Block] = []
    position = 0
    pattern = re.compile(_DISPLAY.pattern + "|" + _BLOCK_MARKER.pattern, re.S)
    for match in pattern.finditer(body):
        before = body[position:match.start()].strip()
        if before:
            out.append(Paragraph(_runs(before)))
        if match.group(1) is not None:
            out.append(DisplayMath(" ".join(match.group(1).split())))
        elif match.group(2) == "figure":
            out.append(FigureRef(match.group(3)))
        else:
            out.append(FormulaRef(match.group(3)))
        position = match.end()
    rest = body[position:].strip()
    if rest:
        out.append(Paragraph(_runs(rest)))
    return out


_INLINE = re.compile(
    r"(?P<code>`[^`]+`)"
    r"|(?P<math>\$[^$]+\$)"
    r"|(?P<field>\{\{[^{}]*\}\})"
    r"|(?P<bold>\*\*)"
    r"|(?P<italic>\*)")


# complexity: the prose dialect's inline scanner: one branch per marker kind
def _runs(body: str) -> tuple[Run, ...]:  # noqa: C901
    runs: list[Run] = []
    bold = italic = False
    position = 0

    def style() -> str:
        if bold and italic:
            return "bold-italic"
        return "bold" if bold else "italic" if italic else "regular"

    def add_text(text: str) -> None:
        if not text:
            return
        if "$" in text:
            raise TextError(f"an unclosed $ in {body[:60]!r}")
        if "{{" in text or "}}" in text:
            raise TextError(f"an unclosed {{{{ in {body[:60]!r}")
        if runs and isinstance(runs[-1], Text) and runs[-1].style == style():
            runs[-1] = Text(runs[-1].text + text, style())
        else:
            runs.append(Text(text, style()))

    for match in _INLINE.finditer(body):
        add_text(body[position:match.start()])
        position = match.end()
        kind = match.lastgroup
        token = match.group(kind)
        if kind == "code":      # live numbers stay live inside code
            inner, at = token[1:-1], 0
            for field in _FIELD.finditer(inner):
                if field.start() > at:
                    runs.append(Text(inner[at:field.start()], "code"))
                runs.append(Value(field.group(1), (field.group(2) or "").strip(), "code"))
                at = field.end()
            if at < len(inner):
                runs.append(Text(inner[at:], "code"))
        elif kind == "math":
            runs.append(Math(token[1:-1].strip()))
        elif kind == "field":
            found = _FIELD.fullmatch(token)
            if found is None:
                raise TextError(f"cannot read the field {token!r}")
            name, argument = found.group(1), (found.group(2) or "").strip()
            if name == "fig":
                if not argument:
                    raise TextError("{{fig:ID}} needs a figure id of the step (or view)")
                runs.append(FigureNumber(argument))
            elif name == "try":
                if not argument.isdigit():
                    raise TextError(f"{{{{try:K}}}} needs a step's try-this number, got "
                                    f"{argument!r}")
                runs.append(TryButton(int(argument)))
            elif name in BLOCK_MARKERS:
                raise TextError(f"{token} must stand in its own paragraph")
            else:
                runs.append(Value(name, argument, style()))
        elif kind == "bold":
            bold = not bold
        else:
            italic = not italic
    add_text(body[position:])
    if bold or italic:
        raise TextError(f"unclosed {'**' if bold else '*'} in {body[:60]!r}")
    return tuple(runs)


def substitute(text: str, value_of) -> str:
    """``text`` with each live number replaced by ``value_of(name, format)`` (markers are
    left alone): used for math, whose LaTeX is typeset after the numbers are filled in."""
    def replace(match: re.Match) -> str:
        name = match.group(1)
        if name in MARKERS:
            return match.group(0)
        return value_of(name, (match.group(2) or "").strip())

    return _FIELD.sub(replace, text)


def all_runs(blocks: tuple[Block, ...]) -> list[Run]:
    """Every run of ``blocks``: paragraphs, list items and table cells."""
    runs: list[Run] = []
    for block in blocks:
        if isinstance(block, (Paragraph, Item)):
            runs.extend(block.runs)
        elif isinstance(block, Table):
            for row in (block.header,) + block.rows:
                for cell in row:
                    runs.extend(cell)
    return runs


def runs_text(runs: tuple[Run, ...]) -> str:
    """The prose of ``runs`` (text runs only), for checks on what is drawn as text."""
    return "".join(run.text for run in runs if isinstance(run, Text))
