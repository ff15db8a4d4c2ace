"""The site's HTML: the page frame, the index, a lesson page, and the pieces of a step
(its view, a try-this swipe, an image sequence, a predict-then-press reveal, the command
that opens it in the window). Plain HTML5 with relative links only, so the site reads
from ``file://`` and from any static host.

Every interactive piece carries ``data-control="NAME"`` (:mod:`explorer.site.controls`),
works from the keyboard, and reads without the script: a swipe then shows its two
pictures side by side, a sequence its first picture without a Play button.
"""

from __future__ import annotations

import html
from dataclasses import dataclass

from explorer.site.controls import attribute

CSS = "assets/site.css"
JS = "assets/site.js"
PHONE_WIDTH = 480
"""Pixels of the phone-size copy of a picture (a 375 px screen at about 1.3×)."""
SIZES = "(max-width: 46rem) 100vw, 44rem"
"""How wide a picture is drawn: the whole phone screen, else the column."""


def esc(text: str) -> str:
    return html.escape(str(text), quote=True)


@dataclass(frozen=True)
class Image:
    """An image file of the site (path relative to the site root) and its pixel size
    (``scale`` 2: a 2× image, shown at half its pixels); ``small``: a phone-size copy
    (path, pixel width) the browser may fetch instead."""

    src: str
    width: int
    height: int
    scale: int = 1
    small: tuple[str, int] | None = None

    def tag(self, alt: str, css: str = "", extra: str = "", lazy: bool = True,
            deferred: bool = False) -> str:
        """The ``<img>``: lazy-loaded unless ``lazy`` is False; ``deferred``: its
        addresses in ``data-src``/``data-srcset`` only, set by the script when the
        picture is first shown (a sequence's later frames)."""
        cls = f' class="{css}"' if css else ""
        prefix = "data-" if deferred else ""
        srcset = ""
        if self.small is not None:
            srcset = (f' {prefix}srcset="{esc(self.small[0])} {self.small[1]}w, '
                      f'{esc(self.src)} {self.width}w" sizes="{SIZES}"')
        loading = ' loading="lazy"' if lazy and not deferred else ""
        return (f'<img {prefix}src="{esc(self.src)}"{srcset} width="{self.width // self.scale}"'
                f' height="{self.height // self.scale}" alt="{esc(alt)}"{cls}{extra}{loading}'
                ' decoding="async">')


def frame(title: str, body: str, nav: str = "", description: str = "") -> str:
    """A whole page: head (title, description, the shipped CSS), the site header,
    ``body`` in ``<main>``, the footer and the shipped script. The root element says
    ``no-js`` until the script runs (the stylesheet lays pictures out for that case)."""
    return f"""<!DOCTYPE html>
<html lang="en" class="no-js">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{esc(title)}</title>
<meta name="description" content="{esc(description)}">
<link rel="stylesheet" href="{CSS}">
<link rel="icon" href="data:,">
</head>
<body>
<a class="skip" href="#main">Skip to the text</a>
<header class="site"><div class="inner"><a class="brand" href="index.html">Light Propagation
Volumes, explained</a>{nav}</div></header>
<main id="main">
{body}
</main>
<footer class="site"><div class="inner">Built from the lessons of lpv-explorer. Every
picture and number on these pages was rendered by its LPV at build time; the explorer
window runs it live (<code>pip install</code> the project, then <code>lpv-explorer
run</code>).</div></footer>
<script src="{JS}"></script>
</body>
</html>
"""


def caption(number: int, text: str) -> str:
    """A figure's caption, starting with its number ("Figure 3.")."""
    return f'<figcaption><span class="fig-no">Figure {number}.</span> {text}</figcaption>'


def figure_id(number: int) -> str:
    return f"fig-{number}"


def enlarge(image: Image, inner: str) -> str:
    """``inner`` (the picture) as a link to the full-size file: a tap opens it."""
    return (f'<a class="enlarge" {attribute("enlarge")} href="{esc(image.src)}" '
            f'aria-label="Open the picture at full size">{inner}</a>')


def view_figure(image: Image, alt: str, text: str, number: int, overlay: str = "",
                lazy: bool = True) -> str:
    """The step's picture (with ``overlay``, its marks, drawn over it) and its caption."""
    picture = image.tag(alt, lazy=lazy)
    picture = f'<div class="view-wrap">{picture}{overlay}</div>' if overlay else picture
    return (f'<figure class="view" id="{figure_id(number)}">{enlarge(image, picture)}'
            f"{caption(number, text)}</figure>")


def inspect_figure(image: Image, alt: str, text: str, number: int) -> str:
    return (f'<figure class="inspect" id="{figure_id(number)}">'
            f"{enlarge(image, image.tag(alt))}{caption(number, text)}</figure>")


def swipe(before: Image, after: Image, before_label: str, after_label: str, alt: str,
          after_alt: str = "") -> str:
    """A before/after pair: the after picture over the before one, clipped at the
    slider's position (drag across the picture, or use the arrow keys). Without the
    script the two pictures stand side by side, each with its label."""
    return (f'<div class="swipe" data-swipe {attribute("swipe")}>'
            f'<div class="before-wrap">{before.tag("Before: " + alt, "before")}'
            f'<span class="tag before">{esc(before_label)}</span></div>'
            f'<div class="after-wrap">{after.tag("After: " + (after_alt or alt), "after")}'
            f'<span class="tag after">{esc(after_label)}</span></div>'
            '<div class="divider"></div>'
            f'<input type="range" min="0" max="100" value="50" step="1" '
            f'aria-valuetext="half and half: {esc(before_label)} left, {esc(after_label)} right"'
            f' aria-label="Swipe between {esc(before_label)} and {esc(after_label)}">'
            "</div>")


def sequence(frames: list[tuple[Image, str]], start: int, title: str, text: str,
             number: int | None = None, css: str = "", rate: float = 3.0,
             alt: str = "") -> str:
    """Frames shown one at a time: a slider to scrub them and Play. Only the start
    frame is fetched with the page; the others when the reader first moves the slider
    or presses Play (the script). Without the script: the start frame, no Play."""
    alt = alt or title
    imgs = "".join(image.tag(f"{alt}: {label}", extra=f' data-label="{esc(label)}"'
                             + ("" if i == start else " hidden"), deferred=i != start)
                   for i, (image, label) in enumerate(frames))
    anchor = f' id="{figure_id(number)}"' if number is not None else ""
    note = caption(number, text) if number is not None else f'<p class="caption">{text}</p>'
    return (f'<figure class="sequence {css}"{anchor} data-sequence {attribute("sequence")} '
            f'data-rate="{rate:g}"><h3>{esc(title)}</h3><div class="frames">{imgs}</div>'
            '<div class="controls"><button type="button" class="play" hidden>Play</button>'
            f'<input type="range" min="0" max="{len(frames) - 1}" value="{start}" '
            f'aria-label="{esc(title)}" aria-valuetext="{esc(frames[start][1])}">'
            f'<output aria-hidden="true">{esc(frames[start][1])}</output></div>'
            f"{note}</figure>")


def try_card(number: int, anchor: str, label: str, pair: str, prompt: str,
             prediction=None) -> str:
    """A try-this: its before/after pair and its prompt. With a ``prediction`` (the
    lesson's "predict, then press": question, choices, 1-based answer) the reader picks a
    choice first; the script hides the pair and the prompt until then (without the
    script they simply show, the answer under the question)."""
    head = f'<h3>Try this {number}: {esc(label)}</h3>'
    body = f'{pair}<p class="prompt">{prompt}</p>'
    if prediction is None:
        return f'<div class="try" id="{esc(anchor)}">{head}{body}</div>'
    right = prediction.choices[prediction.answer - 1]
    choices = "".join(f'<button type="button" class="choice secondary" data-choice="{i}">'
                      f"{esc(choice)}</button>"
                      for i, choice in enumerate(prediction.choices, 1))
    return (f'<div class="try" id="{esc(anchor)}" data-predict {attribute("predict")} '
            f'data-answer="{prediction.answer}">{head}<div class="predict">'
            f"<p><strong>Predict, then pick:</strong> {esc(prediction.question)}</p>"
            f'<div class="choices">{choices}</div><p class="verdict" aria-live="polite">'
            f"<noscript>The answer: {esc(right)}.</noscript></p></div>"
            f'<div class="reveal">{body}</div></div>')


def open_command(lesson_id: str, step: int) -> str:
    command = f"lpv-explorer run --lesson {lesson_id} --step {step}"
    return (f'<p class="open">Open this step in the explorer window, every switch live: '
            f"<code>{esc(command)}</code></p>")


def step_section(number: int, title: str, body: str) -> str:
    return (f'<section class="step" id="step-{number}"><h2><span class="step-no">{number}'
            f"</span>{esc(title)}</h2>\n{body}\n</section>")


def lesson_nav(links: list[tuple[str, str]], current: str) -> str:
    """The lesson menu: every lesson by number and title, the current one marked; a
    disclosure that opens without the script."""
    items = "".join(f'<li><a href="{esc(href)}"' + (' aria-current="page"' if href == current
                                                     else "") + f">{esc(text)}</a></li>"
                    for href, text in links)
    return (f'<details class="lessons"><summary>Lessons</summary><nav aria-label="Lessons">'
            f'<ol>{items}</ol></nav></details>')


def marks_overlay(width: int, height: int,
                  marks: list[tuple[str, tuple, tuple, tuple, bool]]) -> str:
    """Labelled points over a view picture (``width`` × ``height`` pixels): each (label,
    point, label centre, arrow start, visible) a dot at the point with a line from its
    label, faded where a surface hides the point. Dots and lines are an SVG stretched
    over the image; the labels are text placed in percent of it, so they stay readable
    on a phone."""
    if not marks:
        return ""
    lines, labels = [], []
    radius = max(width, height) / 160
    for label, (x, y), (cx, cy), (ax, ay), visible in marks:
        faded = "" if visible else ' class="hidden-mark"'
        lines.append(f'<g{faded}><line x1="{ax:.1f}" y1="{ay:.1f}" x2="{x:.1f}" y2="{y:.1f}"/>'
                     f'<circle cx="{x:.1f}" cy="{y:.1f}" r="{radius:.1f}"/></g>')
        labels.append(f'<span class="mark-label{" hidden-mark" if not visible else ""}" '
                      f'style="left: {100 * cx / width:.2f}%; top: {100 * cy / height:.2f}%">'
                      f"{esc(label)}</span>")
    return (f'<svg class="marks" viewBox="0 0 {width} {height}" preserveAspectRatio="none" '
            f'aria-hidden="true">{"".join(lines)}</svg>{"".join(labels)}')


def glossary_section(terms: list[tuple[str, str, str]]) -> str:
    """The page's terms (anchor, term, meaning) as a definition list: where a term in
    the text leads without the script, and what its popover reads."""
    if not terms:
        return ""
    rows = "".join(f'<dt id="{esc(anchor)}"><dfn>{esc(term)}</dfn></dt>'
                   f'<dd id="{esc(anchor)}-def">{esc(meaning)}</dd>'
                   for anchor, term, meaning in terms)
    return (f'<section class="glossary" id="terms"><h2>Terms on this page</h2>'
            f"<dl>{rows}</dl></section>")


def references_section(references) -> str:
    """The page's sources as full citations (addresses as text: no network needed)."""
    if not references:
        return ""
    items = "".join(f'<li id="ref-{esc(ref.key)}">{esc(ref.citation)}'
                    + (f' <span class="address">{esc(ref.address)}</span>' if ref.address
                       else "") + "</li>" for ref in references)
    return f'<section class="references" id="references"><h2>References</h2><ol>{items}</ol>' \
           "</section>"
