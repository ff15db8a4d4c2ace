"""Live numbers baked into the page: each ``{{name:format}}`` a step quotes, formatted
from the step's converged frame exactly as the window's article formats it
(:func:`explorer.lessons.live_values.render`), with what it measures and its unit in
words on hover or tap. Timings are the build machine's, not the reader's: the page
prints none (:data:`TIMINGS`; the build reports any a lesson's site text still quotes)."""

from __future__ import annotations

import html
import re
from dataclasses import dataclass, field

from explorer.lessons import live_values
from explorer.site.controls import attribute

TIMINGS = ("frame.time.", "frame.timer", "frame.renderer")
"""Quantities that describe the machine that built the site (how long a pass took, on
which renderer): a page that quoted them would state the build machine's speed as fact."""
_CODE_NAME = re.compile(r"\s*\((?:[A-Za-z_]\w*\.)+[A-Za-z_]\w*(?:\(\))?\)"
                        r"|\s*\((?:settings|audit|frame|derived|sh|corrections|error)\.[\w.]+\)")


def plain_words(text: str) -> str:
    """``text`` without the code names in parentheses that the window's tooltips carry
    for programmers ("(Settings.lights)", "(explorer.lpv.stage_list.STAGES)")."""
    return _CODE_NAME.sub("", text)


@dataclass
class Baker:
    """Formats the live numbers of one configuration (one frame) of a step."""

    context: live_values.LiveContext
    figure_ids: tuple[str, ...] = ()
    where: str = ""
    """Where the numbers appear (for the build's report of numbers without a value)."""
    pending: list[str] = field(default_factory=list)
    """Quantities that had no value (``name: reason``), for the build's report."""
    baked: list[tuple[str, str, str]] = field(default_factory=list)
    """(name, format, text) of every number written, in order (tests compare them)."""
    timings: list[str] = field(default_factory=list)
    """Build-machine timings the text quoted (``where name``): the build reports them."""

    def text(self, name: str, fmt: str) -> str:
        """The number as the window writes it (``…`` when it has no value)."""
        shown = live_values.render(name, fmt, self.context, self.figure_ids)
        if name.startswith(TIMINGS):
            self.timings.append(f"{self.where}{name}")
        if shown == live_values.PENDING:
            reason = live_values.pending_reason(name, self.context, self.figure_ids)
            self.pending.append(f"{self.where}{name}: {reason}")
        self.baked.append((name, fmt, shown))
        return shown

    def tooltip(self, name: str) -> str:
        quantity = live_values.lookup(name, self.figure_ids, *_mark_ids(self.context))
        unit = f" [{quantity.unit}]" if quantity.unit else ""
        how = (" Measured on this step's converged frame." if quantity.measured else
               " An exact constant of the model." if quantity.source == "derived" else
               " A setting of this step.")
        doc = plain_words(quantity.doc)
        return f"{doc[:1].upper()}{doc[1:]}{unit}.{how}"

    def attributes(self, name: str, fmt: str, shown: str) -> str:
        return (f'class="live" data-q="{html.escape(name)}" data-fmt="{html.escape(fmt)}" '
                f'title="{html.escape(self.tooltip(name))}" {attribute("live-number")}')

    def span(self, name: str, fmt: str, css: str = "") -> str:
        """The number as an HTML span with its tooltip."""
        shown = self.text(name, fmt)
        extra = f" {css}" if css else ""
        attrs = self.attributes(name, fmt, shown).replace('class="live"',
                                                           f'class="live{extra}"')
        return f"<span {attrs}>{html.escape(shown)}</span>"

    def mn(self, name: str, fmt: str) -> str:
        """The number as a MathML ``<mn>`` with its tooltip (a number inside math)."""
        shown = self.text(name, fmt)
        return f"<mn {self.attributes(name, fmt, shown)}>{html.escape(shown)}</mn>"


def _mark_ids(context: live_values.LiveContext) -> tuple:
    """``lookup``'s mark ids argument, where the lessons place marks (``mark.*``)."""
    marks = getattr(context, "marks", None)
    return () if marks is None else (tuple(marks),)


def context_marks(step) -> dict:
    """The LiveContext keyword for the step's marks (none where lessons have no marks)."""
    from dataclasses import fields

    if "marks" not in {f.name for f in fields(live_values.LiveContext)}:
        return {}
    return {"marks": {mark.id: mark for mark in getattr(step, "marks", ())}}
