"""Build the course site: every chosen lesson rendered, written and checked.

:func:`build_site` renders in three passes so that no frame has to be kept: the imgui
figures first (a child process, :mod:`explorer.site.figure_shots`), then each step's
pictures with the numbers its text quotes baked right away from the frame they belong
to, then the index. The site is written into a fresh folder beside ``out`` and moved
into place at the end, so a failed build leaves a previous site as it was.

Index: :class:`SiteOptions` and :func:`choose_lessons` (what is built), :func:`prepare_out`,
:func:`build_site`, the step's words (:func:`view_words`, :func:`look_hint`,
:func:`try_label`), and ``_Writer``, which writes the pages.
"""

from __future__ import annotations

import json
import shutil
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from explorer.lessons import Lesson, Step, TryThis, live_values
from explorer.lessons import text as lesson_text
from explorer.site import live_figures, live_lpv, pages, prose
from explorer.site.controls import attribute
from explorer.site.frames import (
    FrameRenderer,
    Screen,
    Shot,
    step_screen,
    to_bytes,
    try_screen,
    uses_error,
    uses_truth,
)
from explorer.site.values import Baker, context_marks

MARKER = "lpv-site.json"
"""Written at the site's root: a folder holding it may be replaced by a new build."""
PLOT_KINDS = ("flux-per-step", "energy-audit")
"""Figure kinds drawn as SVG from the step's frames (the others as 2× PNG)."""
SEQUENCE_ITERATIONS = (0, 1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64)
"""The iteration counts an "iterations" sequence shows (up to the largest the step uses)."""
THUMB_WIDTH = 480
MARK_GLYPH_WIDTH, MARK_TEXT_HEIGHT = 7.0, 14.0
"""A mark label's size in picture pixels per character and its height (for placing it)."""
PLOT_OF_PANEL = {"flux-per-step": "flux-per-step", "audit": "energy-audit"}
"""A step's ``plot`` (the Plots panel's tab) -> the figure kind that draws it."""
SHOWN_OVERLAYS = ("slice", "glyphs", "vpls", "lattice", "cascade_boxes", "blockers")
"""The overlays a view's caption names (the others say how these are drawn)."""
JPEG_QUALITY = 88
PHONE_FIGURE_WIDTH = 343
"""CSS pixels of a figure drawn for a phone: a 375 px screen less the page's margins."""
PHONE_KEY = "@phone"
PHONE_MEDIA = "(max-width: 40rem)"


INSPECT_WORDS = {"rsm-position": "the reflective shadow map's positions",
                 "rsm-normal": "the reflective shadow map's normals",
                 "rsm-flux": "the reflective shadow map's flux",
                 "grid-slice": "a slice through the grid",
                 "geometry-volume": "a slice through the geometry volume",
                 "cascade-weights": "the cascade each pixel reads"}
"""A buffer the window's Inspect panel shows, in words (the page shows it as a figure)."""
FIGURE_WORDS = {"clamped-cosine": "The clamped cosine lobe and its spherical-harmonics "
                                  "projection",
                "cell-faces": "A cell's neighbour, its five faces and their solid angles",
                "propagation-stepper": "A small grid propagating step by step",
                "small-multiples": "The same view at several settings side by side",
                "rsm-texel": "One shadow-map texel's beam on a tilted surface",
                "energy-audit": "Where the frame gains and loses flux",
                "flux-per-step": "The flux in flight after each propagation step",
                "pipeline": "The pipeline's stages and the flux that reaches each"}
"""What a figure kind draws, in words (its alt text, and its caption when it has none)."""
ERROR_ALT = ("The LPV's indirect light at the reference's exposure",
             "The one-bounce reference's indirect light",
             "Per pixel, how many stops the LPV is above (red) or below (blue) the reference")
VIEW_WORDS = {"final": "the final image, direct and indirect light",
              "direct": "the direct light alone", "indirect": "the indirect light alone",
              "albedo": "the surfaces' albedo"}


def view_words(step: Step) -> str:
    """What the step's picture shows, in words."""
    if step.view == "split":
        return f"left half this step's formulas, right half the {step.compare_preset} preset"
    if step.view == "difference":
        return (f"the difference between this step and the {step.compare_preset} preset, "
                "the brightest difference white")
    return VIEW_WORDS.get(step.view, "the final image")


def view_alt(step: Step) -> str:
    """The step's picture described for a reader who cannot see it."""
    drawn = shown_in_scene(step)
    extra = f", with {'; '.join(drawn)}" if drawn else ""
    words = view_words(step)
    return f"{words[:1].upper()}{words[1:]} of the {step.scene_name} scene{extra}"


def look_hint(step: Step, numbers: dict[str, int]) -> str:
    """The window's "Look at …" line for the page: which figures to look at, by number."""
    from explorer.site.prose import figure_link
    from explorer.ui.lesson_panel import overlay_words

    drawn = overlay_words(step.overlays())
    parts = [f"{figure_link(numbers['view'])} ({pages.esc(drawn or view_words(step))})"]
    if "inspect" in numbers:
        parts.append(f"{figure_link(numbers['inspect'])} "
                     f"({pages.esc(INSPECT_WORDS.get(step.view, step.view))})")
    for key, words in (("plot", f"the {step.plot} plot"), ("error", "the error images")):
        if key in numbers:
            parts.append(f"{figure_link(numbers[key])} ({pages.esc(words)})")
    return "Look at " + ", ".join(parts[:-1]) + (" and " if len(parts) > 1 else "") + \
        parts[-1] + "."


def values_table(title: str, header: list[str], rows: list[list[str]]) -> str:
    """A plot's values as an HTML table behind a disclosure (read without the picture)."""
    head = "".join(f'<th scope="col">{pages.esc(cell)}</th>' for cell in header)
    body = "".join("<tr>" + "".join(f"<td>{pages.esc(cell)}</td>" for cell in row) + "</tr>"
                   for row in rows)
    return (f'<details class="values"><summary>{pages.esc(title)}</summary>'
            f'<div class="table-wrap"><table><thead><tr>{head}</tr></thead>'
            f"<tbody>{body}</tbody></table></div></details>")


class SiteError(ValueError):
    """A request the build cannot carry out (one line: the lesson, the folder)."""


@dataclass(frozen=True)
class SiteOptions:
    out: Path
    lessons: tuple[str, ...] = ()
    """Lesson ids, numbers or file stems (empty: every lesson)."""
    size: tuple[int, int] = (960, 600)
    """Pixels of each step's 3D view."""
    figure_width: int = 640
    """CSS pixels of an inline figure (drawn at twice that)."""
    lessons_dir: Path | None = None
    image_format: str = "jpg"


@dataclass
class SiteReport:
    out: Path
    pages: list[str] = field(default_factory=list)
    images: int = 0
    bytes: int = 0
    seconds: float = 0.0
    pending: list[str] = field(default_factory=list)
    """Numbers that had no value in their frame (``where name: reason``)."""
    baked: dict[str, list[tuple[str, str, str]]] = field(default_factory=dict)
    """Page section (``lesson/step``) -> (quantity, format, text) of the step's text."""
    timings: list[str] = field(default_factory=list)
    """Build-machine timings a page quotes (``where name``; the lessons' site text should
    quote none)."""
    desktop: list[str] = field(default_factory=list)
    """Interface phrases a page uses without the control that makes them true
    (``page: phrase``, :func:`explorer.site.controls.desktop_phrases`)."""
    weights: dict[str, dict[str, int]] = field(default_factory=dict)
    """Page -> its bytes (:func:`explorer.site.weight.page_weight`)."""

    def summary(self) -> str:
        return (f"site: {len(self.pages)} pages, {self.images} images, "
                f"{self.bytes / 2 ** 20:.1f} MB in {self.out} ({self.seconds:.0f} s)")


def choose_lessons(options: SiteOptions) -> list[Lesson]:
    from explorer.lessons import find_lesson, load_all

    lessons, errors = load_all(options.lessons_dir)
    if errors:
        raise SiteError("broken lesson: " + str(errors[0]))
    if not lessons:
        raise SiteError(f"no lessons in {options.lessons_dir or 'the shipped lessons'}")
    if not options.lessons:
        return lessons
    chosen = []
    for key in options.lessons:
        try:
            lesson = find_lesson(key, lessons, errors)
        except KeyError as exc:
            raise SiteError(exc.args[0]) from None
        if lesson not in chosen:
            chosen.append(lesson)
    return sorted(chosen, key=lambda lesson: lesson.number)


def prepare_out(out: Path) -> Path:
    """The fresh folder to build in (beside ``out``); SiteError when ``out`` is a file or
    a folder with something other than a previous site in it."""
    if out.exists() and not out.is_dir():
        raise SiteError(f"{out} is a file, not a folder")
    if out.is_dir() and any(out.iterdir()) and not (out / MARKER).is_file():
        raise SiteError(f"{out} is not empty and holds no site built by lpv-explorer "
                        f"({MARKER}); name a new or empty folder")
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise SiteError(f"cannot create {out.parent}: {exc.strerror or exc}") from None
    work = out.with_name(f".{out.name}.building")
    if work.exists():
        shutil.rmtree(work)
    work.mkdir()
    return work


def _swap_in(work: Path, out: Path) -> None:
    """Put the built folder ``work`` in place of ``out`` in two renames with the stop
    signals held (explorer/stop_signals.py): the old site or the new one is there whole,
    never neither; the old one is removed after."""
    from explorer.stop_signals import held

    old = out.with_name(f".{out.name}.old")
    with held():
        if old.exists():
            shutil.rmtree(old)
        if out.exists():
            out.rename(old)
        try:
            work.rename(out)
        except BaseException:
            if old.exists() and not out.exists():
                old.rename(out)
            raise
    shutil.rmtree(old, ignore_errors=True)


def build_site(options: SiteOptions, log: Callable[[str], None] = print) -> SiteReport:
    """Build the site into ``options.out``; returns what was written."""
    from explorer.site.figure_shots import run_jobs

    start = time.monotonic()
    lessons = choose_lessons(options)
    out = Path(options.out)
    work = prepare_out(out)
    try:
        writer = _Writer(work, options, log)
        jobs = writer.figure_jobs(lessons)
        log(f"site: drawing {len(jobs)} figures")
        answers = run_jobs(jobs, work / ".figure-work")
        shutil.rmtree(work / ".figure-work", ignore_errors=True)
        writer.figure_answers = answers
        writer.assets()
        for lesson in lessons:
            writer.lesson(lesson, lessons)
        writer.index(lessons)
        writer.report.pending += writer.frames.problems
        writer.release()
        writer.finish()
        (work / MARKER).write_text(json.dumps({"lessons": [lesson.id for lesson in lessons],
                                               "size": list(options.size),
                                               "weights": writer.report.weights},
                                              indent=1) + "\n")
        _swap_in(work, out)
    except BaseException:
        shutil.rmtree(work, ignore_errors=True)
        raise
    report = writer.report
    report.out = out
    report.pages = [str(out / name) for name in writer.page_names]
    files = [path for path in out.rglob("*") if path.is_file()]
    report.images = sum(1 for path in files if path.suffix in (".png", ".jpg", ".svg"))
    report.bytes = sum(path.stat().st_size for path in files)
    report.seconds = time.monotonic() - start
    return report


def _anchor(step: Step, index: int) -> str:
    return f"step-{step.number}-try-{index}"


def try_label(item: TryThis) -> str:
    """The try-this button's text in words: its ``label``, else the control's label from
    the settings schema (or the correction's title) and the value."""
    if item.label:
        return item.label
    button = getattr(item, "button", None)          # the window's own wording, if any
    if callable(button):
        return button()[0]
    from explorer.lessons.live_values import format_value
    from explorer.lpv.corrections import BY_NAME
    from explorer.lpv.settings import Settings
    from explorer.schema import specs

    value = format_value(item.value, "g")
    if item.control.startswith("corrections."):
        name = item.control.split(".", 1)[1]
        title = BY_NAME[name].title if name in BY_NAME else name
        return f"{title}: {value}"
    if item.control == "corrections":
        return f"{value} preset" if isinstance(item.value, str) else "other corrections"
    spec = specs(Settings).get(item.control)
    return f"{(spec.label if spec is not None and spec.label else item.control)}: {value}"


def shown_in_scene(step: Step) -> list[str]:
    """What the step's overlays draw, in the words of their documentation."""
    from dataclasses import fields as dataclass_fields

    from explorer.overlay_params import OverlayState

    docs = {f.name: f.metadata["spec"].doc for f in dataclass_fields(OverlayState)
            if f.metadata and "spec" in f.metadata}
    words = []
    for name, value in step.show:
        if value is True and name in SHOWN_OVERLAYS:
            doc = docs[name].rstrip(".")
            doc = doc[len("Draw "):] if doc.startswith("Draw ") else doc
            words.append(doc if doc[:2].isupper() else doc[:1].lower() + doc[1:])
    return words


class _DualBaker(Baker):
    """A try-this prompt's numbers: the value after the change, and the measured ones'
    value before it beside."""

    def __init__(self, after: Baker, before: Baker) -> None:
        super().__init__(after.context, after.figure_ids, after.where, after.pending,
                         after.baked)
        self.before = before

    def span(self, name: str, fmt: str, css: str = "") -> str:
        after = super().span(name, fmt, css)
        if name.split(".", 1)[0] in ("settings", "corrections"):
            return after            # the change the try-this names: its label says it
        was = self.before.text(name, fmt)
        if was == self.baked[-1][2]:
            return after
        before = self.before.span(name, fmt, "was")
        return f'{after} <span class="was-note">(before: {before})</span>'


class _Writer:
    def __init__(self, root: Path, options: SiteOptions, log: Callable[[str], None]) -> None:
        self.root = root
        self.options = options
        self.log = log
        self.frames = FrameRenderer(*options.size)
        self.figure_answers: dict[str, Any] = {}
        self.report = SiteReport(root)
        self.page_names: list[str] = []
        self.thumbs: dict[str, pages.Image] = {}

    # --- files ---------------------------------------------------------------------------
    def assets(self) -> None:
        from importlib.resources import files

        from explorer.ui.fonts import SYMBOL_FONT, fonts_dir

        folder = self.root / "assets"
        folder.mkdir()
        shipped = files("explorer.site") / "assets"
        for name in ("site.css", "site.js"):
            (folder / name).write_bytes((shipped / name).read_bytes())
        live_figures.copy_assets(folder)
        font = fonts_dir() / SYMBOL_FONT           # Latin Modern Math (GUST font licence)
        licence = font.with_name("GUST-FONT-LICENSE.txt")
        if licence.is_file():
            shutil.copyfile(licence, folder / "GUST-FONT-LICENSE.txt")
        live_lpv.copy_assets(folder)

    def image(self, pixels: np.ndarray, name: str, fmt: str | None = None,
              width: int | None = None, small: bool = False) -> pages.Image:
        """Write ``pixels`` (uint8) as ``img/<name>.<fmt>``; ``small``: and a phone-size
        copy ``img/<name>-small.<fmt>`` when the picture is wider than that."""
        image = self._write(pixels, name, fmt, width)
        if small and image.width > pages.PHONE_WIDTH:
            copy = self._write(pixels, f"{name}-small", fmt, pages.PHONE_WIDTH)
            image = replace(image, small=(copy.src, copy.width))
        return image

    def _write(self, pixels: np.ndarray, name: str, fmt: str | None,
               width: int | None) -> pages.Image:
        from PIL import Image as PilImage

        fmt = fmt or self.options.image_format
        path = self.root / "img" / f"{name}.{fmt}"
        path.parent.mkdir(parents=True, exist_ok=True)
        picture = PilImage.fromarray(np.ascontiguousarray(pixels[..., :3]), "RGB")
        if width is not None and picture.width > width:
            picture = picture.resize((width, round(picture.height * width / picture.width)),
                                     PilImage.LANCZOS)
        if fmt == "jpg":
            picture.save(path, quality=JPEG_QUALITY, optimize=True)
        else:
            picture.save(path, optimize=True)
        return pages.Image(path.relative_to(self.root).as_posix(), picture.width,
                           picture.height)

    # --- figures drawn by the child ------------------------------------------------------
    def figure_jobs(self, lessons: list[Lesson]) -> list[dict[str, Any]]:
        jobs = []
        for lesson in lessons:
            for step in lesson.steps:
                for spec in step.figures:
                    if spec.kind in PLOT_KINDS:
                        continue
                    key = f"{lesson.id}/{step.number}/{spec.instance_id}"
                    out = (self.root / "img" / lesson.id
                           / f"step{step.number}-{spec.instance_id}.png")
                    out.parent.mkdir(parents=True, exist_ok=True)
                    job = {"key": key, "lesson": lesson.id, "step": step.number,
                           "figure": spec.instance_id, "out": str(out),
                           "width": self.options.figure_width,
                           "sequence": spec.kind == "propagation-stepper",
                           "size": list(self.options.size),
                           "lessons_dir": (str(self.options.lessons_dir)
                                           if self.options.lessons_dir else None)}
                    jobs.append(job)
                    if not job["sequence"] and self.options.figure_width > PHONE_FIGURE_WIDTH:
                        # drawn again at a phone's column, so its words stay legible there
                        jobs.append(dict(job, key=key + PHONE_KEY, width=PHONE_FIGURE_WIDTH,
                                         out=str(out.with_name(f"{out.stem}-phone.png"))))
        return jobs

    def _figure_image(self, path: str) -> pages.Image:
        from PIL import Image as PilImage

        with PilImage.open(path) as picture:
            width, height = picture.size
        return pages.Image(Path(path).relative_to(self.root).as_posix(), width, height,
                           scale=2)

    # --- a lesson ------------------------------------------------------------------------
    def lesson(self, lesson: Lesson, lessons: list[Lesson]) -> None:
        from explorer.lessons.glossary import load_glossary
        from explorer.site.controls import reader_text
        from explorer.site.references import cited

        self.log(f"site: lesson {lesson.number:02d} {lesson.id} ({len(lesson.steps)} steps)")
        self.terms = prose.Terms(load_glossary(self.options.lessons_dir))
        self.figure_count = 0
        sections = [self.step(lesson, step) for step in lesson.steps]
        toc = "".join(f'<li><a href="#step-{s.number}">{pages.esc(s.title)}</a></li>'
                      for s in lesson.steps)
        index = lessons.index(lesson)
        pager = ['<nav class="pager" aria-label="Next and previous lessons">']
        if index > 0:
            before = lessons[index - 1]
            pager.append(f'<a href="{page_name(before)}">← {pages.esc(before.title)}</a>')
        pager.append('<a href="index.html">All lessons</a>')
        if index + 1 < len(lessons):
            after = lessons[index + 1]
            pager.append(f'<a href="{page_name(after)}">{pages.esc(after.title)} →</a>')
        pager.append("</nav>")
        width, height = self.options.size
        article = (f"<article><p class=\"kicker\">Lesson {lesson.number}</p>"
                   f"<h1>{pages.esc(lesson.title)}</h1>"
                   f'<p class="summary">{pages.esc(lesson.summary)}</p>'
                   '<p class="rendered">Every still picture on this page was rendered by the '
                   f"LPV at {width}×{height} pixels, converged, when the site was built; every "
                   "number was measured on the frame its step shows.</p>"
                   f'<nav aria-label="Steps of this lesson"><ol class="toc">{toc}</ol></nav>'
                   + "\n".join(sections))
        article += pages.glossary_section(self.terms.used())
        article += pages.references_section(cited(reader_text(article)))
        body = article + "</article>" + "".join(pager)
        body += live_figures.loader_tag(body)
        body += live_lpv.module_script() if any(s.live_lpv for s in lesson.steps) else ""
        name = page_name(lesson)
        nav = pages.lesson_nav([(page_name(one), f"{one.number}. {one.title}")
                                for one in lessons], name)
        (self.root / name).write_text(pages.frame(f"{lesson.title} · LPV lessons", body,
                                                  nav, lesson.summary), encoding="utf-8")
        self.page_names.append(name)

    def shot(self, screen: Screen, step: Step, texts: list[str], error: bool = False) -> Shot:
        return self.frames.shot(screen, step.view, step.overlays(),
                                want_error=error or uses_error(texts),
                                want_truth=uses_truth(texts))

    def context(self, shot: Shot, figures: dict[str, dict[str, float]], step: Step
                ) -> live_values.LiveContext:
        return live_values.LiveContext(settings=shot.settings, result=shot.result,
                                       error=shot.error, figures=figures,
                                       renderer=self.frames.renderer, **context_marks(step))

    def numbers(self, step: Step, has_inspect: bool) -> dict[str, int]:
        """The step's figures (``view``, ``inspect``, its figure ids, ``plot``, ``error``,
        ``iterations``) -> their numbers on the page, in the order the page shows them."""
        placed = [block.id for block in lesson_text.parse(step.text, prose.MEDIUM)
                  if isinstance(block, lesson_text.FigureRef)]
        order = ["view"] + (["inspect"] if has_inspect else [])
        order += placed + [fid for fid in step.figure_ids if fid not in placed]
        if self.panel_plot(step):
            order.append("plot")
        if step.plot == "error":
            order.append("error")
        if any(item.control == "iterations" for item in step.try_this):
            order.append("iterations")
        numbers = {key: self.figure_count + i for i, key in enumerate(order, 1)}
        self.figure_count += len(order)
        return numbers

    def step(self, lesson: Lesson, step: Step) -> str:
        where = f"{lesson.id} step {step.number}: "
        stem = f"{lesson.id}/step{step.number}"
        texts = [step.text] + [spec.caption for spec in step.figures]
        # the prompts' numbers before the change are this frame's too
        shot = self.shot(step_screen(step), step, texts + [t.prompt for t in step.try_this],
                         error=step.plot == "error")
        first = step.number == 1
        view = self.image(shot.image, stem, small=True)
        if first:
            self.thumbs[lesson.id] = self.image(shot.image, f"{stem}-thumb", width=THUMB_WIDTH)
        figures = self.readouts(lesson, step, shot)
        baker = Baker(self.context(shot, figures, step), step.figure_ids, where)
        numbers = self.numbers(step, shot.inspect is not None)
        self.terms.new_step()
        parts = [f'<p class="look">{look_hint(step, numbers)}</p>',
                 pages.view_figure(view, view_alt(step), self.view_caption(step),
                                   numbers["view"], self.marks(step, shot), lazy=not first)]
        if shot.inspect is not None:
            words = INSPECT_WORDS.get(step.view, f"the {step.view.replace('-', ' ')} buffer")
            parts.append(pages.inspect_figure(
                self.image(shot.inspect, f"{stem}-inspect", "png"),
                f"{words[:1].upper()}{words[1:]} of this step's frame",
                f"{pages.esc(words[:1].upper() + words[1:])} for “{pages.esc(step.title)}”, "
                "one pixel per texel or cell.", numbers["inspect"]))
        figure_html = {spec.instance_id: self.figure(lesson, step, spec, shot, baker,
                                                     numbers)
                       for spec in step.figures}
        placed = {block.id for block in lesson_text.parse(step.text, prose.MEDIUM)
                  if isinstance(block, lesson_text.FigureRef)}

        def try_link(index: int) -> str:
            return (f'<a class="try-link" href="#{_anchor(step, index)}">'
                    f"{pages.esc(try_label(step.try_this[index - 1]))}</a>")

        text = prose.blocks(step.text, baker, figure_html.get, try_link, numbers, self.terms)
        parts.append(f'<div class="prose">{text}</div>')
        if step.live_lpv:
            try:
                parts.append(live_lpv.step_figure(self.frames.ctx, step, self.root,
                                                  self.options.size, view.src,
                                                  f"{step.title}: the baked picture"))
            except ValueError as exc:
                raise SiteError(f"{where}{exc}") from None
        parts += [html for fid, html in figure_html.items() if fid not in placed]
        parts += [prose.formula(name, baker) for name in step.formulas]
        if "plot" in numbers:
            parts.append(self.step_plot(step, shot, numbers["plot"]))
        if step.plot == "error" and shot.error_result is not None:
            parts.append(self.error_figure(shot.error_result, baker, stem, numbers["error"],
                                           step.title))
        self.report.baked[f"{lesson.id}/{step.number}"] = list(baker.baked)
        self.report.pending += baker.pending
        self.report.timings += baker.timings
        if "iterations" in numbers:
            parts.append(self.iterations(step, stem, numbers["iterations"]))
        if step.try_this and step_screen(step).mode != "single":
            alone = self.shot(Screen(step.settings()), step, [])     # A without B beside
            view = self.image(alone.image, f"{stem}-a", small=True)
        parts += [self.try_this(step, index, shot, view, figures, stem, where, numbers)
                  for index in range(1, len(step.try_this) + 1)]
        parts.append(pages.open_command(lesson.id, step.number))
        return pages.step_section(step.number, step.title, "\n".join(parts))

    def marks(self, step: Step, shot: Shot) -> str:
        """The step's marks over its picture, placed by the window's own geometry
        (explorer/ui/overlays/marks.py ``placements``); "" for a step without marks."""
        marks = getattr(step, "marks", ())
        if not marks:
            return ""
        from explorer.ui.overlays.marks import placements

        height, width = shot.image.shape[:2]
        placed = placements(shot.result, marks, (0.0, 0.0), (float(width), float(height)),
                            lambda label: (MARK_GLYPH_WIDTH * len(label), MARK_TEXT_HEIGHT))
        return pages.marks_overlay(width, height, [
            (p.label, p.point, ((p.box[0] + p.box[2]) / 2, (p.box[1] + p.box[3]) / 2),
             p.anchor, p.visible) for p in placed])

    def view_caption(self, step: Step) -> str:
        """What the step's picture shows, for this step: its title, the view and what the
        overlays draw in the scene."""
        overlays = shown_in_scene(step)
        extra = f"; drawn in the scene: {'; '.join(overlays)}" if overlays else ""
        return (f"“{pages.esc(step.title)}”: {pages.esc(view_words(step))} of the "
                f"{pages.esc(step.scene_name)} scene{pages.esc(extra)}.")

    # --- inline figures ------------------------------------------------------------------
    def readouts(self, lesson: Lesson, step: Step, shot: Shot) -> dict[str, dict[str, float]]:
        """What each figure of the step reads out: the child's numbers for the figures it
        drew, the audit figures' own readouts of this step's frames."""
        from explorer.ui.figures.host import FigureContext
        from explorer.ui.figures.registry import FIGURES, USES_RESULTS

        values: dict[str, dict[str, float]] = {}
        results = tuple(r for r in (shot.result, shot.compare_result) if r is not None)
        for spec in step.figures:
            kind = FIGURES[spec.kind]
            if spec.kind in USES_RESULTS:
                context = FigureContext(results=results)
                values[spec.instance_id] = {k: float(v) for k, v in kind.readouts(
                    spec.params, kind.make_state(spec.params), context).items()}
            else:
                answer = self.figure_answers.get(f"{lesson.id}/{step.number}/{spec.instance_id}")
                values[spec.instance_id] = dict(answer["readouts"]) if answer else {}
        return values

    def figure(self, lesson: Lesson, step: Step, spec, shot: Shot, baker: Baker,
               numbers: dict[str, int]) -> str:
        number = numbers[spec.instance_id]
        caption = prose.inline(spec.caption, baker, numbers) if spec.caption else ""
        words = caption or pages.esc(FIGURE_WORDS.get(spec.kind, spec.kind.replace("-", " ")))
        caption_html = pages.caption(number, words)
        data = (f'id="{pages.figure_id(number)}" data-figure="{pages.esc(spec.instance_id)}" '
                f'data-kind="{pages.esc(spec.kind)}"')
        if spec.kind in PLOT_KINDS:
            svg, table = self.plot(spec, shot)
            return (f'<figure class="plot" {data} {attribute("plot-points")}>{svg}'
                    f"{caption_html}{table}</figure>")
        answer = self.figure_answers[f"{lesson.id}/{step.number}/{spec.instance_id}"]
        images = [self._figure_image(path) for path in answer["files"]]
        alt = FIGURE_WORDS.get(spec.kind, spec.kind.replace("-", " "))
        if len(images) == 1:
            picture = images[0].tag(alt)
            phone = self.figure_answers.get(
                f"{lesson.id}/{step.number}/{spec.instance_id}{PHONE_KEY}")
            if phone:
                small = self._figure_image(phone["files"][0])
                picture = (f'<picture><source media="{PHONE_MEDIA}" '
                           f'srcset="{pages.esc(small.src)}" width="{small.width // 2}" '
                           f'height="{small.height // 2}">{picture}</picture>')
            html = (f'<figure class="figure" {data}>'
                    f"{pages.enlarge(images[0], picture)}{caption_html}</figure>")
        else:
            # The sequence is the <figure> (with the number's id and caption); the wrapper
            # carries the figure's data without the id, which must stay unique.
            start = min(int(getattr(spec.params, "step", 0)), len(images) - 1)
            wrapper = data.replace(f'id="{pages.figure_id(number)}" ', "")
            html = (f'<div class="figure stepper" {wrapper}>' + pages.sequence(
                [(image, f"step t = {t}") for t, image in enumerate(images)], start,
                "Propagation, step by step", words, number, css="figure-sequence",
                alt=alt) + "</div>")
        return live_figures.with_live(spec, answer["readouts"], caption_html, html)

    def panel_plot(self, step: Step) -> str | None:
        """The plot the step brings forward in the window's Plots panel, when none of its
        figures draws it already (None: no plot)."""
        kind = PLOT_OF_PANEL.get(step.plot or "")
        if kind is None or any(spec.kind == kind for spec in step.figures):
            return None
        return kind

    def step_plot(self, step: Step, shot: Shot, number: int) -> str:
        """The plot the step brings forward in the window's Plots panel: the flux per
        step or the energy audit of this step's frames, its values also as a table."""
        from explorer.figure_params import make_figure

        kind = self.panel_plot(step)
        svg, table = self.plot(make_figure(kind), shot)
        what = ("the flux in flight after each propagation step" if kind == "flux-per-step"
                else "where the frame gains and loses flux")
        return (f'<figure class="plot panel-plot" id="{pages.figure_id(number)}" '
                f'data-plot="{kind}" {attribute("plot-points")}>{svg}'
                + pages.caption(number, f"“{pages.esc(step.title)}”: {what}, measured on "
                                "this step's frame. Hover or tap a point for its value.")
                + f"{table}</figure>")

    def error_figure(self, measured, baker: Baker, stem: str, number: int,
                     title: str) -> str:
        """The Error panel: the LPV's and the reference's indirect light at one exposure
        and log2(LPV / reference) in false colour, with the two numbers it reports."""
        from explorer.lpv.twin.tonemap import linear_to_srgb
        from explorer.truth.progressive import LOG2_SCALE
        from explorer.ui.textures import robust_max

        exposure = 1.0 / robust_max(measured.reference[measured.valid], 99.0)
        pictures = (("LPV", linear_to_srgb(np.nan_to_num(measured.lpv) * exposure)),
                    ("reference", linear_to_srgb(np.nan_to_num(measured.reference) * exposure)),
                    ("log2(LPV / reference)", np.asarray(measured.error.rgb)))
        cells = []
        for index, (title, image) in enumerate(pictures):
            pixels = np.kron(to_bytes(image), np.ones((2, 2, 1), np.uint8))   # 2×, sharp
            picture = self.image(pixels, f"{stem}-error{index}", "png")
            cells.append(f"<div>{pages.enlarge(picture, picture.tag(ERROR_ALT[index]))}"
                         f'<p class="caption">{pages.esc(title)}</p></div>')
        s, m = measured.settings, measured.measurement
        numbers = (f"relative L2 {baker.span('error.relative_l2', '.3f')}, flux ratio "
                   f"LPV / reference {baker.span('error.flux_ratio', '.3f')}")
        return (f'<figure class="error-panel" id="{pages.figure_id(number)}" '
                f'data-plot="error"><div class="triptych">{"".join(cells)}</div>'
                + pages.caption(number, f"“{pages.esc(title)}”: the indirect light against "
                                f"a one-bounce reference: {numbers}. Blue: the LPV is darker "
                                "than the "
                                f"reference, red: brighter; saturates at ±{LOG2_SCALE:g} "
                                f"stops; grey: background. {s.width}×{s.height} pixels, RSM "
                                f"{s.rsm_size}², {pages.esc(m.reference)} reference.")
                + "</figure>")

    def plot(self, spec, shot: Shot) -> tuple[str, str]:
        """The figure's SVG and its values as an HTML table (keyboard and screen readers
        read the table; the SVG's points show the same values on hover or tap)."""
        from explorer.site import plots
        from explorer.ui.figures import energy_audit, plotting
        from explorer.ui.figures.flux_per_step import flux_per_step
        from explorer.ui.figures.results import result_labels

        results = [shot.result] + ([shot.compare_result] if shot.compare_result else [])
        if spec.params.sides == "a":
            results = results[:1]
        labels = result_labels(results)
        if spec.kind == "flux-per-step":
            series = [(label, flux_per_step(r.audit)) for label, r in zip(labels, results)]
            values = np.concatenate([v for _, v in series])
            scale = plotting.choose_scale(values, spec.params.scale)
            rows = [[f"{t}"] + [f"{values[t]:.4g}" if t < len(values) else "" for _, values
                                in series] for t in range(max(len(v) for _, v in series))]
            return (plots.flux_per_step_svg(series, scale, spec.params.relative),
                    values_table("The plotted values", ["step t"] + [
                        f"{label}: flux in flight [W]" for label, _ in series], rows))
        rows = [label for label, _ in energy_audit.AUDIT_ROWS]
        sides = [(label, energy_audit.audit_values(r.audit), float(np.sum(r.audit.injected)))
                 for label, r in zip(labels, results)]
        keep = [i for i, (_, name) in enumerate(energy_audit.AUDIT_ROWS)
                if name not in energy_audit.OPTIONAL_ROWS
                or any(side[1][i] != 0 for side in sides)]
        sides = [(label, v[keep], injected) for label, v, injected in sides]
        every = np.concatenate([np.abs(v) for _, v, _ in sides])
        scale = plotting.choose_scale(every, spec.params.scale)
        table = values_table("The plotted values", ["stage"] + [f"{label} [W]" for label, _, _
                                                                in sides],
                             [[rows[i]] + [f"{v[k]:.4g}" for _, v, _ in sides]
                              for k, i in enumerate(keep)])
        return plots.audit_svg([rows[i] for i in keep], sides, scale,
                               spec.params.relative), table

    # --- exploring: try-this, iterations -------------------------------------------------
    def try_this(self, step: Step, index: int, before_shot: Shot, before: pages.Image,
                 figures: dict, stem: str, where: str, numbers: dict[str, int]) -> str:
        item = step.try_this[index - 1]
        before_baker = Baker(self.context(before_shot, figures, step), step.figure_ids, where)
        after_shot = self.shot(try_screen(step, index), step, [item.prompt])
        after = self.image(after_shot.image, f"{stem}-try{index}", small=True)
        after_baker = Baker(self.context(after_shot, figures, step), step.figure_ids,
                            f"{where}try {index}: ")
        prompt = prose.inline(item.prompt, _DualBaker(after_baker, before_baker), numbers)
        self.report.pending += after_baker.pending + before_baker.pending
        self.report.timings += after_baker.timings + before_baker.timings
        label = try_label(item)
        pair = pages.swipe(before, after, "this step", label, view_alt(step),
                           f"{view_alt(step)}, with {label[:1].lower()}{label[1:]}")
        return pages.try_card(index, _anchor(step, index), label, pair, prompt,
                              getattr(item, "predict", None))

    def iterations(self, step: Step, stem: str, number: int) -> str:
        """The step's view at growing iteration counts, when a try-this changes them."""
        counts = [value for item in step.try_this if item.control == "iterations"
                  for value in item.variants]
        screen = step_screen(step)
        own = int(screen.settings.iterations)
        largest = max([own, *counts])
        wanted = sorted({t for t in SEQUENCE_ITERATIONS if t <= largest} | {own, *counts})
        frames = []
        for t in wanted:
            changed = Screen(screen.settings.with_changes(iterations=t), screen.mode,
                             None if screen.compare is None
                             else screen.compare.with_changes(iterations=t))
            shot = self.frames.shot(changed, step.view, step.overlays())
            image = self.image(shot.image, f"{stem}-iterations{t}", small=True)
            frames.append((image, f"{t} iteration{'' if t == 1 else 's'}"))
        start = wanted.index(own)
        tried = ", ".join(str(c) for c in sorted(set(counts)))
        text = (f"“{pages.esc(step.title)}” from 0 to {largest} propagation steps (the step "
                f"itself uses {own}, its try-this {tried}): light moves one cell per step."
                '<span class="js-only"> Drag the slider or press Play.</span>')
        return pages.sequence(frames, start, "Iterations, one picture each", text, number,
                              rate=2.0, alt=view_alt(step))

    # --- the index -----------------------------------------------------------------------
    def index(self, lessons: list[Lesson]) -> None:
        cards = []
        for position, lesson in enumerate(lessons):
            thumb = self.thumbs.get(lesson.id)
            picture = thumb.tag(f"The first picture of lesson {lesson.number}: "
                                f"{view_alt(lesson.steps[0])}", lazy=position >= 4) \
                if thumb else ""
            outline = "".join(f'<li><a href="{page_name(lesson)}#step-{step.number}">'
                              f"{pages.esc(step.title)}</a></li>" for step in lesson.steps)
            cards.append(f'<li><a href="{page_name(lesson)}">{picture}<div class="text">'
                         f"<h2>{lesson.number}. {pages.esc(lesson.title)}</h2>"
                         f"<p>{pages.esc(lesson.summary)}</p></div></a>"
                         f'<ol class="outline">{outline}</ol></li>')
        body = ("<h1>Light Propagation Volumes, explained</h1>"
                '<p class="summary">A course on Kaplanyan and Dachsbacher\'s real-time '
                "indirect lighting, built from the lessons of lpv-explorer: each lesson a "
                "page, each step with the picture the LPV renders, the numbers measured on "
                "it, and the changes to try.</p>"
                f'<ul class="cards">{"".join(cards)}</ul>')
        nav = pages.lesson_nav([(page_name(one), f"{one.number}. {one.title}")
                                for one in lessons], "index.html")
        (self.root / "index.html").write_text(pages.frame("Light Propagation Volumes, "
                                                          "explained", body, nav),
                                              encoding="utf-8")
        self.page_names.insert(0, "index.html")

    def release(self) -> None:
        self.frames.release()

    def finish(self) -> None:
        """After every page: the math font cut to the pages' glyphs, each page checked
        for interface phrases without their control, and weighed."""
        from explorer.site import weight
        from explorer.site.controls import desktop_phrases
        from explorer.ui.fonts import SYMBOL_FONT, fonts_dir

        written = [self.root / name for name in self.page_names]
        chars, size = weight.subset_math_font(fonts_dir() / SYMBOL_FONT, written,
                                              self.root / "assets" / weight.FONT)
        self.log(f"site: math font: {chars} characters, {size / 1000:.0f} kB as WOFF2")
        for page in written:
            self.report.desktop += [f"{page.name}: {phrase}" for phrase in
                                    desktop_phrases(page.read_text(encoding="utf-8"))]
            self.report.weights[page.name] = weight.page_weight(self.root, page.name)
        for line in weight.report_lines(self.report.weights):
            self.log(line)
        for problem in self.report.timings:
            self.log(f"site: a build-machine timing on a page: {problem}")
        for problem in self.report.desktop:
            self.log(f"site: an interface phrase without its control: {problem}")


def page_name(lesson: Lesson) -> str:
    return f"{lesson.number:02d}-{lesson.id}.html"
