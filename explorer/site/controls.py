"""Which controls a page of the site has, and the phrases only those controls make true.

The lessons were written for the explorer window: "press it again to undo", "the Inspect
panel", "drag the tilt". On a page such a sentence is true only where the page has a
control that does it, so the site keeps two declared lists:

* :data:`PHRASES`: instructions and names that belong to an interface (pressing,
  dragging, hovering, the window's panels and views), each a pattern over the text a
  reader sees;
* :data:`CONTROLS`: the controls a page can hold, each stamped on the page as
  ``data-control="NAME"`` and admitting the phrases it makes true.

A page may use a phrase only when one of the controls that admit it is on the page
(:func:`desktop_phrases`). Modules that add live controls (live figures, a live LPV)
:func:`register` theirs, with the phrases they admit.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from html.parser import HTMLParser


@dataclass(frozen=True)
class Phrase:
    """Words that tell the reader to work a control, or name a part of the window."""

    name: str
    pattern: str
    """A regular expression over the reader's text (case-insensitive)."""

    def find(self, text: str) -> list[str]:
        return [m.group(0) for m in re.finditer(self.pattern, text, re.I)]


@dataclass(frozen=True)
class Control:
    """A control a page can have: ``data-control="name"`` on the element that holds it."""

    name: str
    what: str
    admits: tuple[str, ...]
    """The :data:`PHRASES` it makes true on a page that has it."""


PHRASES: dict[str, Phrase] = {p.name: p for p in (
    Phrase("press", r"\bpress(?:es|ed|ing)?\b"),
    Phrase("click", r"\b(?:double-)?click(?:s|ed|ing)?\b"),
    Phrase("tap", r"\btap(?:s|ped|ping)?\b"),
    Phrase("hover", r"\bhover(?:s|ed|ing)?\b"),
    Phrase("drag", r"\bdrag(?:s|ged|ging)?\b"),
    Phrase("slider", r"\bsliders?\b"),
    Phrase("play", r"\bPlay\b"),
    Phrase("undo", r"\bundo\b|\bagain to (?:go back|restore)\b"),
    # an instruction: "Switch to L2", "turn the clamp off", "toggle it" (not "switching
    # the side faces off", a description)
    Phrase("toggle", r"\b(?:toggle|tick|untick)(?:s|d|ed|ing)?\b"
                     r"|(?:^|[.!?:;]\s+|\b(?:and|then|now|to|please)\s+)(?:switch|turn|flip)"
                     r" (?:\w+ ){0,3}?(?:on|off|to|back)\b"),
    Phrase("pick", r"(?:^|[.!?:;]\s+|\b(?:and|then|now|to)\s+)(?:pick|select|choose) (?:a|the|"
                   r"another) (?:cell|face|light|texel|pixel|point|stage)\b"),
    Phrase("panel", r"\bpanels?\b"),
    Phrase("button", r"\bbuttons?\b"),
    Phrase("main view", r"\bmain view\b"),
    Phrase("inspect", r"\bInspect\b(?! \w+ing)"),
    Phrase("window", r"(?<!explorer )(?<!explorer's )\bwindow(?:'s)?\b(?! function)"),
    Phrase("menu", r"\bmenus?\b|\bdrop-?down\b|\bcheck ?box(?:es)?\b"),
    Phrase("keys", r"\b(?:Ctrl|Alt|Shift|Esc|Space ?bar|WASD)\b|\bkeys?\b"),
    Phrase("camera moves", r"\b(?:orbit|fly|zoom) (?:the camera|around|in|out)\b"),
)}

CONTROLS: dict[str, Control] = {c.name: c for c in (
    Control("swipe", "a before/after picture with a divider to drag",
            ("drag", "slider", "keys")),
    Control("sequence", "pictures shown one at a time, a slider to scrub them and Play",
            ("drag", "slider", "play", "press", "keys")),
    Control("predict", "a question with a button per answer, the change shown after",
            ("press", "click", "tap")),
    Control("plot-points", "a plot whose points and bars show their value on hover or tap",
            ("hover", "tap")),
    Control("live-number", "a measured number whose meaning shows on hover or tap",
            ("hover", "tap")),
    Control("term", "a glossary term whose meaning shows on hover, tap or focus",
            ("hover", "tap")),
    Control("enlarge", "a figure that opens at full size when tapped", ("tap", "click")),
)}


def register(control: Control) -> None:
    """Declare a control that pages may hold (a live figure, a live LPV), with the
    phrases it makes true; each phrase must be one of :data:`PHRASES` (add new ones with
    :func:`register_phrase`)."""
    unknown = [name for name in control.admits if name not in PHRASES]
    if unknown:
        raise ValueError(f"control {control.name!r} admits unknown phrases {unknown}")
    CONTROLS[control.name] = control


def register_phrase(phrase: Phrase) -> None:
    """Declare another interface phrase that a page may use only beside its control."""
    PHRASES[phrase.name] = phrase


def attribute(name: str) -> str:
    """The attribute that marks an element as holding the control ``name``."""
    if name not in CONTROLS:
        raise KeyError(f"no control called {name!r}; known: {sorted(CONTROLS)}")
    return f'data-control="{name}"'


def controls_on(markup: str) -> set[str]:
    """The controls a page's HTML holds (its ``data-control`` attributes)."""
    return set(re.findall(r'data-control="([^"]+)"', markup))


class _ReaderText(HTMLParser):
    """The text a reader sees or hears: element text outside code, scripts, styles and
    TeX annotations, plus the alt, title and aria-label attributes."""

    SKIP = ("code", "script", "style", "annotation")

    def __init__(self) -> None:
        super().__init__()
        self.depth = 0
        self.parts: list[str] = []

    def handle_starttag(self, tag, attrs):
        if tag in self.SKIP:
            self.depth += 1
        elif not self.depth:
            self.parts += [value or "" for name, value in attrs
                           if name in ("title", "alt", "aria-label", "aria-valuetext")]

    def handle_endtag(self, tag):
        if tag in self.SKIP:
            self.depth = max(self.depth - 1, 0)

    def handle_data(self, data):
        if not self.depth:
            self.parts.append(data)


def reader_text(markup: str) -> str:
    """What a reader reads and hears of ``markup`` (see :class:`_ReaderText`)."""
    parser = _ReaderText()
    parser.feed(markup)
    return " ".join(" ".join(parser.parts).split())


def desktop_phrases(markup: str) -> list[str]:
    """The interface phrases of a page that no control on the page makes true, each as
    ``phrase name: "words" in "...context..."``; [] for a page that reads right."""
    present = controls_on(markup)
    admitted = {name for control in present if control in CONTROLS
                for name in CONTROLS[control].admits}
    text = reader_text(markup)
    found = []
    for phrase in PHRASES.values():
        if phrase.name in admitted:
            continue
        for match in re.finditer(phrase.pattern, text, re.I):
            context = text[max(match.start() - 50, 0):match.end() + 30]
            found.append(f'{phrase.name}: "{match.group(0)}" in "…{context}…"')
    return found
