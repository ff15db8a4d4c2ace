"""Build the course site: every chosen lesson rendered, written and checked.

:func:`build_site` renders in three passes so that no frame has to be kept: the imgui
figures first (a child process, :mod:`explorer.site.figure_shots`), then each step's
pictures with the numbers its text quotes baked right away from the frame they belong
to, then the index. The site is written into a fresh folder beside ``out`` and moved
into place at the end, so a failed build leaves a previous site as it was.
"""

from __future__ import annotations

import json
import shutil
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from explorer.lessons import Lesson, Step, TryThis, live_values
from explorer.lessons import text as lesson_text
from explorer.site import live_figures, pages, prose
from explorer.site import live_lpv
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
        (work / MARKER).write_text(json.dumps({"lessons": [lesson.id for lesson in lessons],
                                               "size": list(options.size)}) + "\n")
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
        shutil.copyfile(font, folder / "latinmodern-math.otf")
        licence = font.with_name("GUST-FONT-LICENSE.txt")
        if licence.is_file():
            shutil.copyfile(licence, folder / "GUST-FONT-LICENSE.txt")
        live_lpv.copy_assets(folder)

    def image(self, pixels: np.ndarray, name: str, fmt: str | None = None,
              width: int | None = None) -> pages.Image:
        """Write ``pixels`` (uint8) as ``img/<name>.<fmt>``."""
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
                    jobs.append({"key": key, "lesson": lesson.id, "step": step.number,
                                 "figure": spec.instance_id, "out": str(out),
                                 "width": self.options.figure_width,
                                 "sequence": spec.kind == "propagation-stepper",
                                 "size": list(self.options.size),
                                 "lessons_dir": (str(self.options.lessons_dir)
                                                 if self.options.lessons_dir else None)})
        return jobs

    def _figure_image(self, path: str) -> pages.Image:
        from PIL import Image as PilImage

        with PilImage.open(path) as picture:
            width, height = picture.size
        return pages.Image(Path(path).relative_to(self.root).as_posix(), width, height,
                           scale=2)

    # --- a lesson ------------------------------------------------------------------------
    def lesson(self, lesson: Lesson, lessons: list[Lesson]) -> None:
        self.log(f"site: lesson {lesson.number:02d} {lesson.id} ({len(lesson.steps)} steps)")
        sections = [self.step(lesson, step) for step in lesson.steps]
        toc = "".join(f'<li><a href="#step-{s.number}">{pages.esc(s.title)}</a></li>'
                      for s in lesson.steps)
        index = lessons.index(lesson)
        pager = ['<nav class="pager">']
        if index > 0:
            before = lessons[index - 1]
            pager.append(f'<a href="{page_name(before)}">← {pages.esc(before.title)}</a>')
        pager.append('<a href="index.html">All lessons</a>')
        if index + 1 < len(lessons):
            after = lessons[index + 1]
            pager.append(f'<a href="{page_name(after)}">{pages.esc(after.title)} →</a>')
        pager.append("</nav>")
        body = (f"<article><p class=\"kicker\">Lesson {lesson.number}</p>"
                f"<h1>{pages.esc(lesson.title)}</h1>"
                f'<p class="summary">{pages.esc(lesson.summary)}</p>'
                f'<ol class="toc">{toc}</ol>' + "\n".join(sections) + "</article>"
                + "".join(pager))
        body += live_figures.loader_tag(body)
        body += live_lpv.module_script() if any(s.live_lpv for s in lesson.steps) else ""
        name = page_name(lesson)
        nav = pages.lesson_nav([(page_name(one), f"{one.number}") for one in lessons], name)
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

    def step(self, lesson: Lesson, step: Step) -> str:
        where = f"{lesson.id} step {step.number}: "
        stem = f"{lesson.id}/step{step.number}"
        texts = [step.text] + [spec.caption for spec in step.figures]
        # the prompts' numbers before the change are this frame's too
        shot = self.shot(step_screen(step), step, texts + [t.prompt for t in step.try_this],
                         error=step.plot == "error")
        view = self.image(shot.image, stem)
        if step.number == 1:
            self.thumbs[lesson.id] = self.image(shot.image, f"{stem}-thumb", width=THUMB_WIDTH)
        figures = self.readouts(lesson, step, shot)
        baker = Baker(self.context(shot, figures, step), step.figure_ids, where)
        parts = [pages.view_figure(view, f"{step.title}: the {step.view} view",
                                   self.view_caption(step), self.marks(step, shot))]
        if shot.inspect is not None:
            parts.append(pages.inspect_figure(self.image(shot.inspect, f"{stem}-inspect",
                                                         "png"), step.view))
        figure_html = {spec.instance_id: self.figure(lesson, step, spec, shot, baker)
                       for spec in step.figures}
        placed = {block.id for block in lesson_text.parse(step.text)
                  if isinstance(block, lesson_text.FigureRef)}

        def try_link(index: int) -> str:
            return (f'<a class="try-link" href="#{_anchor(step, index)}">'
                    f"{pages.esc(try_label(step.try_this[index - 1]))}</a>")

        text = prose.blocks(step.text, baker, figure_html.get, try_link)
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
        parts.append(self.step_plot(step, shot))
        if step.plot == "error" and shot.error_result is not None:
            parts.append(self.error_figure(shot.error_result, baker, stem))
        self.report.baked[f"{lesson.id}/{step.number}"] = list(baker.baked)
        self.report.pending += baker.pending
        sequence = self.iterations(step, stem)
        if sequence:
            parts.append(sequence)
        if step.try_this and step_screen(step).mode != "single":
            alone = self.shot(Screen(step.settings()), step, [])     # A without B beside
            view = self.image(alone.image, f"{stem}-a")
        parts += [self.try_this(step, index, shot, view, figures, stem, where)
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
        words = {"final": "the final image (direct + indirect)", "direct": "the direct light",
                 "indirect": "the indirect light alone", "albedo": "the surfaces' albedo",
                 "split": f"left: this step's formulas, right: the {step.compare_preset} preset",
                 "difference": f"|this step − the {step.compare_preset} preset|, brightest "
                               "difference white"}
        shows = words.get(step.view, "the final image; the Inspect panel shows "
                                     f"{step.view}")
        overlays = shown_in_scene(step)
        extra = f"; in the scene: {'; '.join(overlays)}" if overlays else ""
        return (f"The {pages.esc(step.scene_name)} scene: {pages.esc(shows)}{pages.esc(extra)}. "
                f"Rendered at {self.options.size[0]}×{self.options.size[1]} by the LPV, "
                "converged.")

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

    def figure(self, lesson: Lesson, step: Step, spec, shot: Shot, baker: Baker) -> str:
        caption = prose.inline(spec.caption, baker) if spec.caption else ""
        caption_html = f"<figcaption>{caption}</figcaption>" if caption else ""
        data = f'data-figure="{pages.esc(spec.instance_id)}" data-kind="{pages.esc(spec.kind)}"'
        if spec.kind in PLOT_KINDS:
            return (f'<figure class="plot" {data}>{self.plot(spec, shot)}{caption_html}'
                    "</figure>")
        answer = self.figure_answers[f"{lesson.id}/{step.number}/{spec.instance_id}"]
        images = [self._figure_image(path) for path in answer["files"]]
        if len(images) == 1:
            html = (f'<figure class="figure" {data}>{images[0].tag(spec.kind)}{caption_html}'
                    "</figure>")
        else:
            start = min(int(getattr(spec.params, "step", 0)), len(images) - 1)
            html = (f'<figure class="figure stepper" {data}>' + pages.sequence(
                [(image, f"step t = {t}") for t, image in enumerate(images)], start,
                "Propagation, step by step", caption or "", css="figure-sequence") + "</figure>")
        return live_figures.with_live(spec, answer["readouts"], caption_html, html)

    def step_plot(self, step: Step, shot: Shot) -> str:
        """The plot the step brings forward in the window's Plots panel (its ``plot``),
        unless one of its figures already draws it: the flux per step or the energy
        audit of this step's frames."""
        from explorer.figure_params import make_figure

        kind = PLOT_OF_PANEL.get(step.plot or "")
        if kind is None or any(spec.kind == kind for spec in step.figures):
            return ""
        svg = self.plot(make_figure(kind), shot)
        what = ("flux in flight after each propagation step" if kind == "flux-per-step"
                else "where the frame gains and loses flux")
        return (f'<figure class="plot panel-plot" data-plot="{kind}">{svg}<figcaption>The '
                f"Plots panel for this frame: {what}. Hover or tap a point for its value."
                "</figcaption></figure>")

    def error_figure(self, measured, baker: Baker, stem: str) -> str:
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
            cells.append(f"<div>{picture.tag(title)}<p class=\"caption\">{pages.esc(title)}"
                         "</p></div>")
        s, m = measured.settings, measured.measurement
        numbers = (f"relative L2 {baker.span('error.relative_l2', '.3f')}, flux ratio "
                   f"LPV / reference {baker.span('error.flux_ratio', '.3f')}")
        return (f'<figure class="error-panel" data-plot="error"><div class="triptych">'
                f"{''.join(cells)}</div><figcaption>The Error panel for this frame: "
                f"{numbers}. Blue: the LPV is darker than the one-bounce reference, red: "
                f"brighter; saturates at ±{LOG2_SCALE:g} stops; grey: background. "
                f"{s.width}×{s.height} px, RSM {s.rsm_size}², {pages.esc(m.reference)} "
                "reference, indirect light only.</figcaption></figure>")

    def plot(self, spec, shot: Shot) -> str:
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
            return plots.flux_per_step_svg(series, scale, spec.params.relative)
        rows = [label for label, _ in energy_audit.AUDIT_ROWS]
        sides = [(label, energy_audit.audit_values(r.audit), float(np.sum(r.audit.injected)))
                 for label, r in zip(labels, results)]
        keep = [i for i, (_, name) in enumerate(energy_audit.AUDIT_ROWS)
                if name not in energy_audit.OPTIONAL_ROWS
                or any(side[1][i] != 0 for side in sides)]
        sides = [(label, v[keep], injected) for label, v, injected in sides]
        every = np.concatenate([np.abs(v) for _, v, _ in sides])
        scale = plotting.choose_scale(every, spec.params.scale)
        return plots.audit_svg([rows[i] for i in keep], sides, scale, spec.params.relative)

    # --- exploring: try-this, iterations -------------------------------------------------
    def try_this(self, step: Step, index: int, before_shot: Shot, before: pages.Image,
                 figures: dict, stem: str, where: str) -> str:
        item = step.try_this[index - 1]
        before_baker = Baker(self.context(before_shot, figures, step), step.figure_ids, where)
        after_shot = self.shot(try_screen(step, index), step, [item.prompt])
        after = self.image(after_shot.image, f"{stem}-try{index}")
        after_baker = Baker(self.context(after_shot, figures, step), step.figure_ids,
                            f"{where}try {index}: ")
        prompt = prose.inline(item.prompt, _DualBaker(after_baker, before_baker))
        self.report.pending += after_baker.pending + before_baker.pending
        label = try_label(item)
        pair = pages.swipe(before, after, "this step", label, step.title)
        return pages.try_card(index, _anchor(step, index), label, pair, prompt,
                              getattr(item, "predict", None))

    def iterations(self, step: Step, stem: str) -> str:
        """The step's view at growing iteration counts, when a try-this changes them."""
        counts = [item.value for item in step.try_this if item.control == "iterations"]
        if not counts:
            return ""
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
            image = self.image(shot.image, f"{stem}-iterations{t}")
            frames.append((image, f"iterations = {t}"))
        start = wanted.index(own)
        return pages.sequence(frames, start, "Iterations, one picture each",
                              "The same step with more and more propagation steps: light "
                              "moves one cell per step. Drag the slider or press Play.",
                              rate=2.0)

    # --- the index -----------------------------------------------------------------------
    def index(self, lessons: list[Lesson]) -> None:
        cards = []
        for lesson in lessons:
            thumb = self.thumbs.get(lesson.id)
            picture = thumb.tag(f"Lesson {lesson.number}: {lesson.title}") if thumb else ""
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
        (self.root / "index.html").write_text(pages.frame("Light Propagation Volumes, "
                                                          "explained", body),
                                              encoding="utf-8")
        self.page_names.insert(0, "index.html")

    def release(self) -> None:
        self.frames.release()


def page_name(lesson: Lesson) -> str:
    return f"{lesson.number:02d}-{lesson.id}.html"
