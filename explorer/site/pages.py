"""The site's HTML: the page frame, the index, a lesson page, and the pieces of a step
(its view, a try-this swipe, an image sequence, a predict-then-press reveal, the command
that opens it in the window). Plain HTML5 with relative links only, so the site reads
from ``file://`` and from any static host."""

from __future__ import annotations

import html
from dataclasses import dataclass

CSS = "assets/site.css"
JS = "assets/site.js"


def esc(text: str) -> str:
    return html.escape(str(text), quote=True)


@dataclass(frozen=True)
class Image:
    """An image file of the site (path relative to the site root) and its pixel size
    (``scale`` 2: a 2× image, shown at half its pixels)."""

    src: str
    width: int
    height: int
    scale: int = 1

    def tag(self, alt: str, css: str = "", extra: str = "") -> str:
        cls = f' class="{css}"' if css else ""
        return (f'<img src="{esc(self.src)}" width="{self.width // self.scale}" '
                f'height="{self.height // self.scale}" alt="{esc(alt)}"{cls}{extra} '
                f'decoding="async">')


def frame(title: str, body: str, nav: str = "", description: str = "") -> str:
    """A whole page: head (title, description, the shipped CSS), the site header,
    ``body`` in ``<main>``, the footer and the shipped script."""
    return f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{esc(title)}</title>
<meta name="description" content="{esc(description)}">
<link rel="stylesheet" href="{CSS}">
</head>
<body>
<header class="site"><div class="inner"><a class="brand" href="index.html">Light Propagation
Volumes, explained</a>{nav}</div></header>
<main>
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


def view_figure(image: Image, alt: str, caption: str, overlay: str = "") -> str:
    """The step's picture (with ``overlay``, its marks, drawn over it) and its caption."""
    picture = f'<div class="view-wrap">{image.tag(alt)}{overlay}</div>' if overlay else \
        image.tag(alt)
    return f'<figure class="view">{picture}<figcaption>{caption}</figcaption></figure>'



def inspect_figure(image: Image, view: str) -> str:
    return (f'<figure class="inspect">{image.tag(f"The {view} view")}<figcaption>The '
            f"Inspect panel: <code>{esc(view)}</code>, one pixel per texel or cell."
            "</figcaption></figure>")


def swipe(before: Image, after: Image, before_label: str, after_label: str, alt: str) -> str:
    """A before/after pair: the after picture over the before one, clipped at the
    slider's position (drag across the picture, or use the arrow keys)."""
    return (f'<div class="swipe" data-swipe>{before.tag("before: " + alt, "before")}'
            f'<div class="after-wrap">{after.tag("after: " + alt, "after")}</div>'
            '<div class="divider"></div>'
            f'<span class="tag before">{esc(before_label)}</span>'
            f'<span class="tag after">{esc(after_label)}</span>'
            f'<input type="range" min="0" max="100" value="50" step="1" '
            f'aria-label="Swipe between {esc(before_label)} and {esc(after_label)}">'
            "</div>")


def sequence(frames: list[tuple[Image, str]], start: int, title: str, caption: str,
             css: str = "", rate: float = 3.0) -> str:
    """Frames shown one at a time: a slider to scrub them and Play."""
    imgs = "".join(image.tag(f"{title}: {label}", extra=f' data-label="{esc(label)}"'
                             + ("" if i == start else " hidden"))
                   for i, (image, label) in enumerate(frames))
    return (f'<div class="sequence {css}" data-sequence data-rate="{rate:g}">'
            f"<h3>{esc(title)}</h3><div class=\"frames\">{imgs}</div>"
            '<div class="controls"><button type="button" class="play">Play</button>'
            f'<input type="range" min="0" max="{len(frames) - 1}" value="{start}" '
            f'aria-label="{esc(title)}"><output>{esc(frames[start][1])}</output></div>'
            f'<p class="caption">{caption}</p></div>')


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
    return (f'<div class="try" id="{esc(anchor)}" data-predict '
            f'data-answer="{prediction.answer}">{head}<div class="predict">'
            f"<p><strong>Predict, then press:</strong> {esc(prediction.question)}</p>"
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
    items = " · ".join(f'<a href="{esc(href)}"' + (' aria-current="page"' if href == current
                                                   else "") + f">{esc(text)}</a>"
                       for href, text in links)
    return f'<nav class="lessons">{items}</nav>'


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
