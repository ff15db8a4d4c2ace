"""A text-flow widget: lesson prose laid out in lines like a page, drawn with imgui.

Blocks come from :mod:`explorer.lessons.text`. Within a paragraph every run becomes boxes
(a word with its trailing space, an inline formula, a live number, a button) that
:func:`layout` breaks into lines no wider than the column and aligns on a common baseline:
a formula typeset by MicroTeX sits with its own baseline (``RenderedFormula.baseline_y``)
on the text's. Display formulas are centred and typeset smaller when they would not fit;
figures are drawn at the column's width by their own code.

:func:`layout` is pure (boxes in, positioned lines out) so its rules are tested without a
window; :class:`Page` measures and draws with imgui.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from copy import copy
from dataclasses import dataclass, field
from typing import Any

from explorer.lessons import text as lt

MIN_DISPLAY_SCALE = 0.55
"""A display formula wider than the column is typeset down to this scale, then squeezed."""
PARAGRAPH_GAP = 0.6
"""Space after a block, in lines of body text."""
LAYOUT_ENTRIES = 1024
"""Paragraphs whose measured boxes and lines :class:`Page` keeps (a step's text is laid
out once, not every frame; the whole cache is dropped when it is full)."""
_BOXES: dict[tuple, list] = {}
"""(the runs as drawn, fonts, metrics) -> the paragraph's boxes (:meth:`Page.boxes`)."""
_LINES: dict[tuple, list] = {}
"""(the boxes' key, width, leading) -> the paragraph's lines (:meth:`Page.paragraph`)."""


@dataclass
class Box:
    """One unbreakable piece of a line. ``ascent``/``descent``: above/below the baseline;
    ``space``: width of the trailing space (dropped at the end of a line)."""

    width: float
    ascent: float
    descent: float
    kind: str                 # "text" | "math" | "value" | "button"
    payload: Any = None
    space: float = 0.0
    glue: bool = False
    """No break allowed before this box (it follows the previous one without a space,
    e.g. a comma after a formula)."""
    x: float = 0.0            # set by layout: left edge relative to the column


@dataclass
class Line:
    boxes: list[Box] = field(default_factory=list)
    ascent: float = 0.0
    descent: float = 0.0
    y: float = 0.0            # top of the line relative to the paragraph

    @property
    def height(self) -> float:
        return self.ascent + self.descent


def layout(boxes: list[Box], width: float, min_ascent: float = 0.0,
           min_descent: float = 0.0, leading: float = 0.0) -> list[Line]:
    """Greedy line breaking: boxes stay in order, a line takes boxes while they fit in
    ``width`` (its trailing space excluded); a box wider than the column gets a line of
    its own; a glued box moves to the next line together with the box(es) it is glued
    to. Each line's ascent and descent are the largest of its boxes (at least the
    font's), so text and formulas share one baseline; ``leading`` is added between
    lines."""
    lines: list[Line] = []
    current = Line()
    x = 0.0
    for box in boxes:
        if current.boxes and x + box.width > width + 1e-6:
            carried: list[Box] = []
            if box.glue:
                # the chain of glued boxes this one ends moves along, unless it is all
                # the line holds
                head = len(current.boxes) - 1
                while head > 0 and current.boxes[head].glue:
                    head -= 1
                if head > 0:
                    carried = current.boxes[head:]
                    current.boxes = current.boxes[:head]
            lines.append(current)
            current, x = Line(), 0.0
            for moved in carried:
                moved.x = x
                current.boxes.append(moved)
                x += moved.width + moved.space
        box.x = x
        current.boxes.append(box)
        x += box.width + box.space
    if current.boxes:
        lines.append(current)
    y = 0.0
    for line in lines:
        line.ascent = max([min_ascent] + [b.ascent for b in line.boxes])
        line.descent = max([min_descent] + [b.descent for b in line.boxes])
        line.y = y
        y += line.height + leading
    return lines


def column_widths(widest: list[float], weights: list[float], width: float) -> list[float]:
    """Widths of a table's columns sharing ``width`` in proportion to ``weights``, except
    that a column narrower than its widest unbreakable box (``widest``: a word never
    breaks) gets that width and the others share what is left. When even the widest
    boxes do not fit, the columns share ``width`` in proportion to them."""
    total = sum(widest)
    if total >= width:
        return [width * w / total for w in widest] if total > 0 else [0.0] * len(widest)
    fixed: dict[int, float] = {}
    while True:
        free = [k for k in range(len(weights)) if k not in fixed]
        room = width - sum(fixed.values())
        share = sum(weights[k] for k in free)
        widths = {k: room * weights[k] / share for k in free}
        short = [k for k in free if widths[k] < widest[k]]
        if not short:
            return [fixed.get(k, widths.get(k, 0.0)) for k in range(len(weights))]
        fixed.update({k: widest[k] for k in short})


_WORDS = re.compile(r"\S+\s*|\s+")


def words(text: str) -> list[tuple[str, bool]]:
    """``text`` cut after each run of spaces: (word, followed by a space) pairs. A run
    that starts with a space (after a formula) keeps it as a word of its own."""
    out = []
    for piece in _WORDS.findall(text):
        stripped = piece.rstrip()
        if not stripped:
            out.append(("", True))
        else:
            out.append((stripped, len(stripped) < len(piece)))
    return out


@dataclass
class PageEnv:
    """What a page reads while it draws (all callbacks return plain data)."""

    fonts: Any = None                          # explorer.ui.fonts.Fonts or None
    formulas: Any = None                       # explorer.ui.formulas.FormulaCache or None
    value: Callable[[str, str], tuple[str, str]] = lambda name, fmt: (name, "")
    """(name, format) -> (text shown, tooltip)."""
    button: Callable[[int], tuple[str, str, bool]] = lambda index: (f"try {index}", "", False)
    """try index -> (label, tooltip, active)."""
    on_button: Callable[[int], None] = lambda index: None
    figure: Callable[[str, float], None] = lambda figure_id, width: None
    formula: Callable[[str], tuple[str, str]] = lambda name: (name, "")
    """derivation name -> (LaTeX with its left-hand side, statement)."""
    page: Any = None
    """The Page drawing with this environment (figures lay out their captions with it)."""
    glossary: tuple = ()
    """``explorer.lessons.glossary.Term`` entries: their words show the meaning on hover."""


class _FormulaShown:
    """A typeset formula in a layout key: equal while the same image at the same size
    (the formula cache's object, held so that its id is not reused)."""

    __slots__ = ("formula", "key")

    def __init__(self, formula: Any) -> None:
        self.formula = formula
        self.key = (id(formula), formula.texture_id, formula.width, formula.height,
                    formula.baseline)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, _FormulaShown) and self.key == other.key

    def __hash__(self) -> int:
        return hash(self.key)


def _kept(cache: dict, key: tuple, value: list) -> list:
    """``value`` stored under ``key`` (the cache dropped first when full)."""
    if len(cache) >= LAYOUT_ENTRIES:
        cache.clear()
    cache[key] = value
    return value


ACCENT = (0.45, 0.72, 1.0, 1.0)
BUTTON_TEXT = (1.0, 0.80, 0.40, 1.0)
CODE_BG = (1.0, 1.0, 1.0, 0.07)
DIM = (0.62, 0.64, 0.68, 1.0)


class Page:
    """Draws blocks into the current imgui window, ``width`` pixels wide from the cursor."""

    def __init__(self, env: PageEnv, width: float) -> None:
        from imgui_bundle import imgui

        self.imgui = imgui
        self.env = env
        self.width = max(float(width), 40.0)
        self.size = env.fonts.body_size if env.fonts is not None else imgui.get_font_size()
        style = imgui.get_style()
        self._fonts_key = (id(env.fonts), self.size, style.font_scale_main,
                           style.font_scale_dpi, env.glossary)
        """What a word's measured width depends on besides its text and style (the
        fonts object lives as long as the window's fonts)."""
        self._words_font: str | None = None
        """The style whose font :meth:`draw_box` left pushed for the next word."""

    # -- fonts -----------------------------------------------------------------------
    def push(self, style: str) -> None:
        font = self.env.fonts.get(style) if self.env.fonts is not None else None
        self.imgui.push_font(font, self.size)

    def pop(self) -> None:
        self.imgui.pop_font()

    def metrics(self) -> tuple[float, float]:
        """(ascent, descent) of the body font at the body size, in pixels."""
        self.push("regular")
        baked = self.imgui.get_font_baked()
        ascent, descent = float(baked.ascent), float(-baked.descent)
        self.pop()
        return ascent, descent

    def text_width(self, text: str, style: str) -> float:
        self.push(style)
        width = self.imgui.calc_text_size(text).x
        self.pop()
        return width

    # -- blocks ----------------------------------------------------------------------
    def draw(self, blocks: tuple) -> None:
        imgui = self.imgui
        ascent, descent = self.metrics()
        gap = (ascent + descent) * PARAGRAPH_GAP
        for index, block in enumerate(blocks):
            imgui.push_id(index)
            if isinstance(block, lt.Paragraph):
                self.paragraph(block.runs, 0.0, ascent, descent)
            elif isinstance(block, lt.Item):
                self.paragraph(block.runs, ascent * 1.4, ascent, descent, block.marker)
            elif isinstance(block, lt.DisplayMath):
                latex = lt.substitute(block.latex, lambda n, f: self.env.value(n, f)[0])
                self.display(latex, "")
            elif isinstance(block, lt.FormulaRef):
                latex, statement = self.env.formula(block.name)
                self.display(latex, statement)
            elif isinstance(block, lt.Table):
                self.table(block, ascent, descent)
            elif isinstance(block, lt.FigureRef):
                self.env.figure(block.id, self.width)
            imgui.pop_id()
            imgui.dummy((self.width, gap))

    def paragraph(self, runs, indent: float, ascent: float, descent: float,
                  marker: str | None = None) -> None:
        imgui = self.imgui
        lines = self.lines(runs, indent, ascent, descent)
        origin = imgui.get_cursor_screen_pos()
        if marker:
            self.push("regular")
            imgui.set_cursor_screen_pos((origin.x + indent * 0.25, origin.y + (
                lines[0].ascent - ascent if lines else 0.0)))
            imgui.text_colored(imgui.ImVec4(*DIM), marker)
            self.pop()
        try:
            for number, line in enumerate(lines):
                top = origin.y + line.y
                for box_number, box in enumerate(line.boxes):
                    x = origin.x + indent + box.x
                    y = top + line.ascent - box.ascent
                    if box.kind == "button":         # the only box with an ID of its own
                        imgui.push_id(number * 1000 + box_number)
                        self.draw_box(box, x, y)
                        imgui.pop_id()
                    else:
                        self.draw_box(box, x, y)
        finally:
            self._release_font()
        height = (lines[-1].y + lines[-1].height) if lines else 0.0
        imgui.set_cursor_screen_pos(origin)
        imgui.dummy((self.width, height))

    def lines(self, runs, indent: float, ascent: float, descent: float) -> list[Line]:
        """The paragraph's lines at the column's width less ``indent``, laid out once
        while its boxes and the width stay the same."""
        key, boxes = self._measured(runs, ascent, descent)
        leading = (ascent + descent) * 0.22
        where = (key, self.width - indent, leading)
        lines = _LINES.get(where)
        if lines is None:       # (layout sets each box's x: copies, as boxes are shared)
            lines = _kept(_LINES, where, layout([copy(box) for box in boxes],
                                                self.width - indent, ascent, descent, leading))
        return lines

    def table(self, block: lt.Table, ascent: float, descent: float) -> None:
        """A table as wide as the column, each cell laid out like a paragraph; a column
        is at least as wide as its widest word (:func:`column_widths`), so that a long
        heading such as "Screen-space" stays within its cell."""
        imgui = self.imgui
        flags = (imgui.TableFlags_.borders_inner_h | imgui.TableFlags_.borders_outer
                 | imgui.TableFlags_.row_bg | imgui.TableFlags_.sizing_stretch_prop)
        columns = len(block.header)
        header = tuple(tuple(lt.Text(r.text, "bold") if isinstance(r, lt.Text) else r
                             for r in runs) for runs in block.header)
        rows = (header,) + block.rows
        widest = [max((box.width for runs in (row[column] for row in rows)
                       for box in self.boxes(runs, ascent, descent)), default=0.0)
                  for column in range(columns)]
        padding = imgui.get_style().cell_padding.x * 2
        first = 0.7 if columns > 2 else 1.0     # the row names' column a little narrower
        # the cells' text widths: the table's width less each cell's padding and the
        # borders (one pixel each); imgui shares the width in proportion to the weights
        widths = column_widths(widest, [first] + [1.0] * (columns - 1),
                               self.width - columns * (padding + 1.0) - 1.0)
        if not imgui.begin_table("##table", columns, flags, (self.width, 0)):
            return
        for column in range(columns):
            imgui.table_setup_column(f"##c{column}", imgui.TableColumnFlags_.width_stretch,
                                     widths[column] + padding)
        outer = self.width
        for row_number, row in enumerate(rows):
            imgui.table_next_row()
            for column, runs in enumerate(row):
                imgui.table_set_column_index(column)
                imgui.push_id(row_number * 100 + column)
                self.width = max(imgui.get_content_region_avail().x, 20.0)
                self.paragraph(runs, 0.0, ascent, descent)
                imgui.pop_id()
        self.width = outer
        imgui.end_table()

    def boxes(self, runs, ascent: float, descent: float) -> list[Box]:
        """The paragraph's boxes, measured (kept while what they show is the same)."""
        return self._measured(runs, ascent, descent)[1]

    def _measured(self, runs, ascent: float, descent: float) -> tuple[tuple, list[Box]]:
        """(key, boxes) of ``runs``: the key holds what the boxes show this frame (each
        live number's text and tooltip, each formula's typeset image, each button's
        label and state), so that a paragraph is measured again only when that changes."""
        resolved = tuple(self._resolve(run) for run in runs)
        key = (resolved, ascent, descent, self._fonts_key)
        boxes = _BOXES.get(key)
        if boxes is None:
            boxes = self._boxes(resolved, ascent, descent)
            for before, box in zip(boxes, boxes[1:]):
                box.glue = before.space == 0.0
            _kept(_BOXES, key, boxes)
        return key, boxes

    def _resolve(self, run) -> object:
        """A run as this frame draws it: text as it is; a live number, a formula and a
        try button with what they show now (the formula as its typeset image)."""
        if isinstance(run, lt.Value):
            return ("value", run.style, *self.env.value(run.name, run.format))
        if isinstance(run, lt.Math):
            latex = lt.substitute(run.latex, lambda n, f: self.env.value(n, f)[0])
            formula = (self.env.formulas.get(latex, 1.0, inline=True)
                       if self.env.formulas is not None else None)
            shown = None if formula is None or not formula.texture_id else (
                _FormulaShown(formula))
            return ("math", latex, shown)
        if isinstance(run, lt.TryButton):
            return ("button", run.index, *self.env.button(run.index))
        return run

    def _boxes(self, resolved: tuple, ascent: float, descent: float) -> list[Box]:
        imgui = self.imgui
        out: list[Box] = []
        space = self.text_width(" ", "regular")
        for run in resolved:
            if isinstance(run, lt.Text):
                pieces = words(run.text)
                tips = self._glossary_tips([word for word, _ in pieces])
                for index, (word, spaced) in enumerate(pieces):
                    if not word:
                        if out:
                            out[-1].space = space
                        continue
                    out.append(Box(self.text_width(word, run.style), ascent, descent, "text",
                                   (word, run.style, tips.get(index)),
                                   space if spaced else 0.0))
            elif run[0] == "value":
                _, style, text, tooltip = run
                out.append(Box(self.text_width(text, style), ascent, descent, "value",
                               (text, style, tooltip)))
            elif run[0] == "math":
                _, latex, shown = run
                if shown is None:
                    out.append(Box(self.text_width(latex, "code"), ascent, descent, "text",
                                   (latex, "code")))
                else:
                    formula = shown.formula
                    out.append(Box(float(formula.width), float(formula.baseline),
                                   float(formula.height - formula.baseline), "math", formula))
            elif run[0] == "button":
                _, index, label, tooltip, active = run
                pad = imgui.get_style().frame_padding.x
                out.append(Box(self.text_width(label, "regular") + 2 * pad, ascent, descent,
                               "button", (index, label, tooltip, active)))
        return out

    def _glossary_tips(self, pieces: list[str]) -> dict[int, str]:
        """Word index -> the glossary's meaning, for the words of a glossary term."""
        if not self.env.glossary:
            return {}
        from explorer.lessons.glossary import matches

        tips = {}
        for first, count, term in matches(pieces, self.env.glossary):
            for index in range(first, first + count):
                tips[index] = f"{term.term}: {term.meaning}"
        return tips

    def _font_for_words(self, style: str) -> None:
        """Draw the next words in ``style``: the font stays pushed from word to word of one
        style (:meth:`_release_font` pops it), not pushed and popped for each word."""
        if self._words_font != style:
            self._release_font()
            self.push(style)
            self._words_font = style

    def _release_font(self) -> None:
        if self._words_font is not None:
            self.pop()
            self._words_font = None

    def draw_box(self, box: Box, x: float, y: float) -> None:
        imgui = self.imgui
        imgui.set_cursor_screen_pos((x, y))
        if box.kind == "text":
            word, style, tip = box.payload
            if style == "code":
                draw = imgui.get_window_draw_list()
                draw.add_rect_filled((x - 2, y), (x + box.width + 2, y + box.ascent + box.descent),
                                     imgui.get_color_u32(imgui.ImVec4(*CODE_BG)), 3.0)
            self._font_for_words(style)
            imgui.text_unformatted(word)
            if tip:
                self._release_font()     # the tooltip in the window's own font
                # a dotted underline says "hover me"; the tooltip holds the meaning
                draw = imgui.get_window_draw_list()
                colour = imgui.get_color_u32(imgui.ImVec4(*DIM))
                base = y + box.ascent + box.descent - 1.0
                for dot in range(int(box.width // 4) + 1):
                    draw.add_line((x + 4 * dot, base), (x + 4 * dot + 2, base), colour, 1.0)
                if imgui.is_item_hovered():
                    imgui.begin_tooltip()
                    imgui.push_text_wrap_pos(imgui.get_font_size() * 24.0)
                    imgui.text_unformatted(tip)
                    imgui.pop_text_wrap_pos()
                    imgui.end_tooltip()
        elif box.kind == "value":
            text, style, tooltip = box.payload
            self._font_for_words(style)
            imgui.text_colored(imgui.ImVec4(*ACCENT), text)
            self._release_font()
            if tooltip and imgui.is_item_hovered():
                imgui.set_tooltip(tooltip)
        elif box.kind == "math":
            self._release_font()
            formula = box.payload
            imgui.image(imgui.ImTextureRef(formula.texture_id),
                        (float(formula.width), float(formula.height)))
        elif box.kind == "button":
            self._release_font()
            index, label, tooltip, active = box.payload
            self.push("regular")
            colour = (0.20, 0.42, 0.75, 1.0) if active else (0.30, 0.24, 0.10, 1.0)
            imgui.push_style_color(imgui.Col_.button, imgui.ImVec4(*colour))
            imgui.push_style_color(imgui.Col_.text, imgui.ImVec4(*BUTTON_TEXT))
            if imgui.small_button(f"{label}##try{index}"):
                self.env.on_button(index)
            imgui.pop_style_color(2)
            self.pop()
            if tooltip and imgui.is_item_hovered():
                imgui.set_tooltip(tooltip)

    def display(self, latex: str, statement: str) -> None:
        """A display formula centred in the column, typeset smaller if it is too wide."""
        imgui = self.imgui
        formulas = self.env.formulas
        origin = imgui.get_cursor_screen_pos()
        formula = formulas.get(latex, 1.15) if formulas is not None else None
        if formula is not None and formula.texture_id and formula.width > self.width:
            scale = max(1.15 * self.width / formula.width, MIN_DISPLAY_SCALE)
            formula = formulas.get(latex, scale)
        if formula is None or not formula.texture_id:
            self.push("code")
            imgui.push_text_wrap_pos(origin.x + self.width)
            imgui.text_wrapped(latex)
            imgui.pop_text_wrap_pos()
            self.pop()
        else:
            width, height = float(formula.width), float(formula.height)
            if width > self.width:
                height *= self.width / width
                width = self.width
            imgui.set_cursor_screen_pos((origin.x + (self.width - width) * 0.5, origin.y))
            imgui.image(imgui.ImTextureRef(formula.texture_id), (width, height))
            if statement and imgui.is_item_hovered():
                imgui.set_tooltip(statement)
        if statement:
            cursor = imgui.get_cursor_screen_pos()
            imgui.set_cursor_screen_pos((origin.x, cursor.y))
            self.push("italic")
            # the wrap position is in the window's coordinates, not the screen's
            imgui.push_text_wrap_pos(imgui.get_cursor_pos_x() + self.width)
            imgui.text_colored(imgui.ImVec4(*DIM), statement)
            imgui.pop_text_wrap_pos()
            self.pop()
