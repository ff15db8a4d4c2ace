"""What a page of the site weighs, and the math font cut down to what the pages typeset.

:func:`page_weight` counts the bytes a browser fetches for a page before the reader does
anything: the HTML, the stylesheet and script, the math font where the page has math, and
the pictures of its first :data:`FIRST_STEPS` steps (lazy or not: a browser fetches
lazy pictures near the screen at once); and, apart, every picture it fetches later
(as the reader scrolls, a sequence's frames when it is first played).
:func:`subset_math_font` writes the font with only the glyphs the pages use, as WOFF2.
"""

from __future__ import annotations

import posixpath
import re
import statistics
from html.parser import HTMLParser
from pathlib import Path

BUDGET = 1_000_000
"""Bytes the median lesson page may weigh before interaction."""
FIRST_STEPS = 2
"""Steps whose pictures count as fetched with the page: a browser loads lazy pictures
that come within about a screen or two of the view (Chromium, 1280 and 375 px wide)."""
FONT = "latinmodern-math.woff2"
LIVE_FIGURES_LOADER = "assets/lpv-modules.js"
"""The live figures' loader (explorer/site/live_figures.py): it adds their stylesheet and
imports assets/figures/live.js, which imports each live kind's module of the page."""
LIVE_LPV_ENTRY = "assets/lpv/live.js"
"""The live LPV's module (explorer/site/live_lpv.py), started once the page is parsed."""
_IMPORTED = re.compile(r"""(?:\bimport\s*(?:[\w*{}\s,$]+?\s*from\s*)?|\bimport\s*\(\s*|"""
                       r"""new\s+URL\(\s*)["'`]([^"'`$]+)["'`]""")
"""A module's static imports, literal dynamic imports and workers (``new URL(...)``)."""
_KIND_MODULES = re.compile(r'"([a-z-]+)":\s*"([a-z]+)"')


class _Resources(HTMLParser):
    """The files a page names: its stylesheet and script, its pictures up to the end of
    the first steps (``first``: what a browser fetches before the reader scrolls, since
    it loads lazy pictures near the screen at once) and after it (``later``)."""

    def __init__(self) -> None:
        super().__init__()
        self.first: list[str] = []
        self.later: list[str] = []
        self.assets: list[str] = []
        self.math = False
        self.live_kinds: list[str] = []
        self.live_lpv = False
        self.steps_ended = 0
        self.past_first_steps = False

    def handle_starttag(self, tag, attrs):
        values = dict(attrs)
        if tag == "img":
            source = values.get("src") or values.get("data-src") or ""
            deferred = "data-src" in values
            (self.later if self.past_first_steps or deferred else self.first).append(source)
        elif tag == "source" and values.get("srcset"):       # a phone's drawing
            (self.later if self.past_first_steps else self.first).append(
                values["srcset"].split()[0])
        elif tag == "link" and values.get("rel") == "stylesheet":
            self.assets.append(values["href"])
        elif tag == "script" and values.get("src"):
            self.assets.append(values["src"])
        elif tag == "math":
            self.math = True
        if values.get("data-live-kind"):
            self.live_kinds.append(values["data-live-kind"])
        if "data-live-lpv" in values:
            self.live_lpv = True

    def handle_endtag(self, tag):
        if tag == "section":              # steps are the only sections before the terms
            self.steps_ended += 1
            self.past_first_steps = self.steps_ended >= FIRST_STEPS


def page_weight(root: Path, page: str) -> dict[str, int]:
    """Bytes of ``page`` (a file under ``root``): ``html``, ``assets`` (CSS, script, the
    math font if the page typesets math), ``pictures`` of the first steps (the largest
    candidate of a srcset: a wide screen's), ``first`` (their sum: before interaction)
    and ``later`` (every other picture, fetched as the reader scrolls or plays)."""
    path = root / page
    parser = _Resources()
    parser.feed(path.read_text(encoding="utf-8"))
    assets = _assets(root, parser)

    def size(names: list[str]) -> int:
        return sum((root / name).stat().st_size for name in dict.fromkeys(names)
                   if name and (root / name).is_file())

    weight = {"html": path.stat().st_size, "assets": size(assets),
              "pictures": size(parser.first), "later": size(parser.later)}
    weight["first"] = weight["html"] + weight["assets"] + weight["pictures"]
    return weight


def first_files(root: Path, page: str) -> set[str]:
    """The files :func:`page_weight` counts before interaction (paths under ``root``)."""
    parser = _Resources()
    parser.feed((root / page).read_text(encoding="utf-8"))
    return {page, *_assets(root, parser), *parser.first}


def _assets(root: Path, parser: _Resources) -> list[str]:
    """Stylesheets and scripts the page names, the math font where it typesets math, and
    the ES modules its live parts import as they start (with what those import)."""
    assets = list(parser.assets) + ([f"assets/{FONT}"] if parser.math else [])
    entries = []
    if LIVE_FIGURES_LOADER in parser.assets and parser.live_kinds:
        assets.append("assets/live-figures.css")
        entry = "assets/figures/live.js"
        modules = dict(_KIND_MODULES.findall(_read(root, entry)))
        entries += [entry, *(f"assets/figures/{modules[kind]}.js"
                             for kind in parser.live_kinds if kind in modules)]
    if parser.live_lpv and LIVE_LPV_ENTRY.replace("live.js", "live.css") in parser.assets:
        entries.append(LIVE_LPV_ENTRY)
    return assets + _module_closure(root, entries)


def _module_closure(root: Path, entries: list[str]) -> list[str]:
    """``entries`` and every module they import, transitively (paths under ``root``;
    ``lpv/<path>`` is the import map's name for ``assets/<path>``)."""
    seen: list[str] = []
    todo = list(entries)
    while todo:
        module = todo.pop()
        if module in seen or not (root / module).is_file():
            continue
        seen.append(module)
        for name in _IMPORTED.findall(_read(root, module)):
            todo.append("assets/" + name[len("lpv/"):] if name.startswith("lpv/") else
                        posixpath.normpath(posixpath.join(posixpath.dirname(module), name)))
    return seen


def _read(root: Path, name: str) -> str:
    return (root / name).read_text(encoding="utf-8") if (root / name).is_file() else ""


def median_first(weights: dict[str, dict[str, int]]) -> float:
    """The median bytes before interaction of the lesson pages (not the index)."""
    lessons = [w["first"] for page, w in weights.items() if page != "index.html"]
    return float(statistics.median(lessons)) if lessons else 0.0


class _MathText(HTMLParser):
    """The characters inside ``<math>`` elements, outside their TeX annotations."""

    def __init__(self) -> None:
        super().__init__()
        self.depth = 0
        self.annotation = 0
        self.chars: set[str] = set()

    def handle_starttag(self, tag, attrs):
        self.depth += tag == "math"
        self.annotation += tag == "annotation"

    def handle_endtag(self, tag):
        self.depth -= tag == "math" and self.depth > 0
        self.annotation -= tag == "annotation" and self.annotation > 0

    def handle_data(self, data):
        if self.depth and not self.annotation:
            self.chars.update(data)


def math_characters(pages: list[Path]) -> set[str]:
    """Every character the pages typeset as MathML."""
    parser = _MathText()
    for page in pages:
        parser.feed(page.read_text(encoding="utf-8"))
    return {c for c in parser.chars if not c.isspace()}


def subset_math_font(source: Path, pages: list[Path], out: Path) -> tuple[int, int]:
    """Write ``source`` (an OpenType math font) with the glyphs of the characters the
    pages typeset, their size variants and assembly parts (the MATH table's closure) and
    the layout features, as WOFF2 at ``out``; returns (characters, bytes)."""
    from fontTools import subset

    chars = math_characters(pages) | set("0123456789()[]{}|=+−-/")
    options = subset.Options()
    options.flavor = "woff2"
    options.layout_features = ["*"]
    options.notdef_outline = True
    options.name_IDs = ["*"]
    options.drop_tables += ["FFTM"]          # FontForge's timestamps: nothing to subset
    font = subset.load_font(str(source), options)
    subsetter = subset.Subsetter(options)
    subsetter.populate(unicodes=sorted(ord(c) for c in chars))
    subsetter.subset(font)
    if "MATH" not in font:
        raise ValueError(f"{source.name}: the subset lost its MATH table")
    subset.save_font(font, str(out), options)
    return len(chars), out.stat().st_size


def report_lines(weights: dict[str, dict[str, int]]) -> list[str]:
    """One line per page, then the median lesson page against :data:`BUDGET`."""
    def kb(n: int) -> str:
        return f"{n / 1000:.0f} kB"

    lines = [f"site: {page}: {kb(w['first'])} before interaction (HTML {kb(w['html'])}, "
             f"CSS, script and font {kb(w['assets'])}, pictures {kb(w['pictures'])}); "
             f"{kb(w['later'])} more as the reader scrolls and plays"
             for page, w in weights.items()]
    median = median_first(weights)
    verdict = "within" if median <= BUDGET else "OVER"
    lines.append(f"site: median lesson page {kb(int(median))} before interaction, {verdict} "
                 f"the {kb(BUDGET)} budget")
    return lines

