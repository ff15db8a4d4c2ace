"""The Lesson panel: a lesson step read as an article, with the 3D view beside it.

The step's text is laid out by the text flow (``explorer/ui/textflow.py``): prose, inline
and display math typeset by MicroTeX, live numbers filled from the frame on screen
(``explorer/lessons/live_values.py``), inline figures (``explorer/ui/figures``) and try-this
buttons. A try-this button applies exactly its change on top of the step (a second click
undoes it; comparing ones show before | after as their ``compare`` says); leaving the lesson gives
the reader's own settings back (:class:`~explorer.ui.lesson_panel.LessonSession`).
"""

from __future__ import annotations

import sys
from dataclasses import replace
from typing import TYPE_CHECKING

from imgui_bundle import imgui

from explorer.lessons import Lesson, Step, live_values
from explorer.lessons import text as lesson_text
from explorer.lessons.words import for_reader
from explorer.ui import widgets
from explorer.ui.article_header import goto_step, header
from explorer.ui.article_numbers import (
    PROVISIONAL,
    figure_context,
    live_context,
    pending_audit,
    provisional,
    uses_audit,
    uses_error,
)
from explorer.ui.article_try import ON_SCREEN, OWN_FRAME, frame_words, try_label, try_section
from explorer.ui.lesson_list import lesson_list
from explorer.ui.lesson_panel import (
    LessonSession,
    current_screen,
    session_of,
    show_screen,
    step_caption,
)
from explorer.ui.textflow import Page, PageEnv

if TYPE_CHECKING:
    from explorer.ui.state import AppState

MAX_COLUMN = 720.0
"""Widest the text column gets (pixels at scale 1): longer lines read badly."""
TITLE_SCALE = 1.35


def gui_article(state: AppState) -> None:
    session = session_of(state)
    sync_requested(state, session)
    if session.lesson is None:
        lesson_list(state, session)
        return
    if not header(state, session):
        return                       # "< All lessons": the list shows from the next frame
    imgui.separator()
    scroll = session.opening_scroll()       # a new step opens at its top
    if scroll is not None:
        imgui.set_next_window_scroll((-1.0, scroll))
    imgui.begin_child("article", (0, 0), imgui.ChildFlags_.none,
                      imgui.WindowFlags_.always_vertical_scrollbar)
    try:
        _article(state, session)
        if session.resume_frames > 0:            # until the text's height is known
            session.resume_frames -= 1
            imgui.set_scroll_y(session.scroll)
        else:
            session.keep_scroll(imgui.get_scroll_y())
    finally:
        imgui.end_child()


def sync_requested(state: AppState, session: LessonSession) -> None:
    """Follow ``state.lesson_id`` / ``state.lesson_step`` (``run --lesson ID --step K``):
    open the lesson at that step and apply it."""
    wanted = state.lesson_id
    if not wanted:
        return
    step = state.lesson_step
    same = session.lesson is not None and wanted in (session.lesson.id,
                                                     session.lesson.path.stem)
    if same and step is None:
        return
    try:
        lesson = session.open(wanted)
        if step is not None:
            lesson.step(step)          # IndexError names the range
            session.go(step)
    except (KeyError, IndexError) as exc:
        state.lesson_id = state.lesson_step = None
        state.notify(str(exc.args[0]), "error")
        return
    state.lesson_id, state.lesson_step = session.lesson.id, None
    show_screen(state, session.apply(current_screen(state)))


def column_width(avail: float) -> float:
    """The text column's width in an article ``avail`` pixels wide: 6 px kept free, at
    most :data:`MAX_COLUMN` (at the style's font scale)."""
    return min(avail - 6.0, MAX_COLUMN * imgui.get_style().font_scale_dpi)


def _article(state: AppState, session: LessonSession) -> None:
    step = session.step
    avail = imgui.get_content_region_avail().x
    width = column_width(avail)
    left = imgui.get_cursor_pos_x() + max((avail - width) * 0.5, 0.0)
    imgui.set_cursor_pos_x(left)
    state.runtime.want_audit(uses_audit(step))
    context = live_context(state, step)
    env = _page_env(state, session, step, context)
    page = Page(env, width)
    env.page = page
    try:
        _draw_article(state, session, step, page, context, width)
    finally:
        # the page and its callbacks form cycles the cyclic collector frees late (a
        # frame kept steps past its step that way): drop the page and the live numbers'
        # frame now
        env.page = None
        env.source.clear()


def _draw_article(state: AppState, session: LessonSession, step: Step, page: Page,
                  context: live_values.LiveContext, width: float) -> None:
    imgui.begin_group()
    page.push("bold")
    imgui.push_font(None, page.size * TITLE_SCALE)
    imgui.push_text_wrap_pos(imgui.get_cursor_pos_x() + width)
    imgui.text_wrapped(step.title)
    imgui.pop_text_wrap_pos()
    imgui.pop_font()
    page.pop()
    page.push("italic")
    imgui.push_text_wrap_pos(imgui.get_cursor_pos_x() + width)
    imgui.text_colored(widgets.DIM, step_caption(step))
    imgui.pop_text_wrap_pos()
    page.pop()
    imgui.spacing()
    if uses_error(step) and context.error is None:
        _error_banner(state)
    blocks = lesson_text.parse(step.text)
    page.draw(blocks)
    placed = {b.id for b in blocks if isinstance(b, lesson_text.FigureRef)}
    shown = {b.name for b in blocks if isinstance(b, lesson_text.FormulaRef)}
    rest = tuple(lesson_text.FigureRef(spec.instance_id) for spec in step.figures
                 if spec.instance_id not in placed)
    rest += tuple(lesson_text.FormulaRef(name) for name in step.formulas if name not in shown)
    if rest:
        page.draw(rest)
    if step.try_this:
        try_section(state, session, page, step)
    _next_step(state, session, width)
    imgui.end_group()


def _page_env(state: AppState, session: LessonSession, step: Step,
              context: live_values.LiveContext) -> PageEnv:
    from explorer import derived

    source = {"context": context, "where": frame_words(session)}

    converging = state.runtime.frame.progress.get("A")

    def value(name: str, fmt: str) -> tuple[str, str]:
        quantity = live_values.lookup(name, step.figure_ids, step.mark_ids)
        text = live_values.render(name, fmt, source["context"], step.figure_ids)
        unit = f" [{quantity.unit}]" if quantity.unit else ""
        tip = f"{for_reader(quantity.doc)}{unit}"
        if (converging and text != live_values.PENDING
                and source["where"] in (ON_SCREEN, OWN_FRAME) and provisional(quantity)):
            text = PROVISIONAL + text
            tip += (f"\nprovisional: read from the frame while it converges "
                    f"({converging}); it settles with the frame")
        elif text == live_values.PENDING:
            tip += "\n(not available yet: " + (
                "measure it in the Error panel)" if quantity.source == "error"
                else pending_audit(name, source["context"], step.figure_ids)
                or f"{source['where']})")
        elif quantity.constant:
            tip += "\na fixed property of the pipeline: no setting changes it"
        elif quantity.measured:
            tip += f"\nmeasured on {source['where']}; it changes with the settings"
        return text, tip

    def button(index: int) -> tuple[str, str, bool]:
        label, tip = try_label(step.try_this[index - 1])
        active = session.tried == index and session.applied
        return ("Undo: " + label if active else label), tip, active

    def on_button(index: int) -> None:
        show_screen(state, session.toggle_try(index, current_screen(state)))

    def figure(figure_id: str, width: float) -> None:
        from explorer.ui.figures import draw_figure

        page = env.page
        spec = next(s for s in step.figures if s.instance_id == figure_id)
        with figure_context(state).showing(state) as context_figures:
            cache = state.runtime.services.figure_cache
            if cache is None:
                draw_figure(replace(spec, caption=""), width, context_figures)
            else:       # drawn once while nothing it shows changes (explorer/ui/figure_cache.py)
                cache.draw(replace(spec, caption=""), width, context_figures, step)
        if spec.caption:      # through the text flow: it may quote live numbers
            caption = lesson_text.parse(spec.caption)
            runs = tuple(lesson_text.Text(r.text, "italic") if isinstance(r, lesson_text.Text)
                         else r for r in lesson_text.all_runs(caption))
            page.push("italic")
            imgui.push_style_color(imgui.Col_.text, widgets.DIM)
            page.paragraph(runs, 0.0, *page.metrics())
            imgui.pop_style_color()
            page.pop()

    def formula(name: str) -> tuple[str, str]:
        result = derived.get(name)
        return result.latex, result.statement

    services = state.runtime.services
    env = PageEnv(fonts=services.fonts, formulas=services.formulas, value=value,
                  button=button, on_button=on_button, figure=figure, formula=formula,
                  glossary=_glossary(session))
    env.source = source
    return env


def _glossary(session: LessonSession) -> tuple:
    """The glossary of the session's lessons (explorer/lessons/glossary.py), read once: the
    course's terms and those of the reader's folder (its spelling of a term wins); none
    from a file that is missing or broken (the lessons command reports a broken one)."""
    cached = session.glossary
    if cached is None:
        from explorer.lessons.glossary import GlossaryError, load_glossary

        terms: dict[str, object] = {}
        for folder in (None, session.folder) if session.folder else (None,):
            try:
                found = load_glossary(folder)
            except GlossaryError as exc:
                print(f"lpv-explorer: {exc}", file=sys.stderr)
                found = ()
            terms.update({term.term.lower(): term for term in found})
        cached = session.glossary = tuple(terms.values())
    return cached


def _error_banner(state: AppState) -> None:
    from explorer.ui.panels.error import error_service

    service = error_service(state)
    if service.running:
        job = service.job
        imgui.progress_bar(job.fraction, (-1, 0),
                           f"measuring the error against the reference: {job.fraction:.0%}")
        return
    widgets.dim_text_wrapped("The numbers marked … are measured against the reference "
                             "renderer; the Error panel computes them in the background.")
    if imgui.small_button("Measure now"):
        service.measure()
        state.requests.focus_panel = ("Error",)


NEXT_MIN_SCALE = 0.8
"""The next button's title shrinks to this share of the font at the least."""


def _next_button(what: str, title: str, width: float) -> bool:
    """The button to the next step or lesson with its title on it, in a smaller font when
    it is wider than the column (a cut label reads as a broken one); a title too long even
    so goes under a short button."""
    label = f"{what}: {title}  >"
    width = min(width, imgui.get_content_region_avail().x)
    padding = 2 * imgui.get_style().frame_padding.x
    if imgui.calc_text_size(label).x + padding <= width:
        return imgui.button(label)
    full = imgui.get_font_size()
    size = full * (width - padding) / imgui.calc_text_size(label).x
    while size >= NEXT_MIN_SCALE * full:        # glyph widths round at a size: measure
        imgui.push_font(None, size)
        if imgui.calc_text_size(label).x + padding <= width:
            pressed = imgui.button(label)
            imgui.pop_font()
            return pressed
        imgui.pop_font()
        size -= 0.5
    pressed = imgui.button(f"{what}  >")
    imgui.push_text_wrap_pos(imgui.get_cursor_pos_x() + width)
    imgui.text_colored(widgets.DIM, title)
    imgui.pop_text_wrap_pos()
    return pressed


def _next_step(state: AppState, session: LessonSession, width: float) -> None:
    imgui.spacing()
    if session.step_number < session.step_count:
        following = session.lesson.step(session.step_number + 1)
        if _next_button("Next", following.title, width):
            session.next()
            goto_step(state, session)
    else:
        index = session.lessons.index(session.lesson) if session.lesson in session.lessons \
            else -1
        if 0 <= index < len(session.lessons) - 1:
            following: Lesson = session.lessons[index + 1]
            if _next_button("Next lesson", following.title, width):
                session.open(following.id)
                state.lesson_id = following.id
                goto_step(state, session)
    imgui.dummy((width, 24))
