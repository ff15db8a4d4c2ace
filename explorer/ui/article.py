"""The Lesson panel: a lesson step read as an article, with the 3D view beside it.

The step's text is laid out by the text flow (``explorer/ui/textflow.py``): prose, inline
and display math typeset by MicroTeX, live numbers filled from the frame on screen
(``explorer/lessons/live_values.py``), inline figures (``explorer/ui/figures``) and try-this
buttons. A try-this button applies exactly its change on top of the step (a second click
undoes it; ``split`` ones show before | after in the split view); leaving the lesson gives
the reader's own settings back (:class:`~explorer.ui.lesson_panel.LessonSession`).
"""

from __future__ import annotations

import sys
from dataclasses import replace
from typing import TYPE_CHECKING

from imgui_bundle import imgui

from explorer.figure_params import FIGURE_KINDS
from explorer.lessons import Lesson, Step, TryThis, live_values
from explorer.lessons import text as lesson_text
from explorer.lessons.words import for_reader
from explorer.ui import widgets
from explorer.ui.lesson_panel import (
    LessonSession,
    current_screen,
    session_of,
    show_screen,
    shows_step,
    step_caption,
)
from explorer.ui.textflow import Page, PageEnv
from explorer.ui.try_numbers import same_frame

if TYPE_CHECKING:
    from explorer.ui.state import AppState

MAX_COLUMN = 720.0
"""Widest the text column gets (pixels at scale 1): longer lines read badly."""
TITLE_SCALE = 1.35


# --- labels ------------------------------------------------------------------------------

def try_label(item: TryThis) -> tuple[str, str]:
    """(button text, tooltip) of a try-this, in words (``TryThis.button``): the
    control's label and the value, its documentation as tooltip."""
    label, tip = item.button()
    tip = for_reader(tip)
    if item.split:
        tip += "\nShown as before | after in the split view."
    return label, tip


# --- live numbers ------------------------------------------------------------------------

def live_context(state: AppState, step: Step) -> live_values.LiveContext:
    """What the step's placeholders read now (figures: those the step quotes)."""
    from explorer.ui.panels.error import current_stats, want_truth

    rt = state.runtime
    if uses_truth(step):
        want_truth(state)
    figures = {}
    wanted = {name.split(".")[1] for text in _texts(step)
              for name, _ in lesson_text.placeholders(text) if name.startswith("figure.")}
    if wanted:
        from explorer.ui.figures import FIGURES

        context = figure_context(state)
        for spec in step.figures:
            if spec.instance_id in wanted:
                kind = FIGURES[spec.kind]
                instance = context.state_for(spec.instance_id, spec.kind, spec.params,
                                             kind.make_state)
                figures[spec.instance_id] = kind.readouts(spec.params, instance, context)
    return live_values.LiveContext(settings=state.settings, result=rt.frame.result,
                                   error=current_stats(state), figures=figures,
                                   renderer=rt.services.gl_renderer,
                                   marks={mark.id: mark for mark in step.marks})


def _texts(step: Step) -> list[str]:
    return [step.text] + [t.prompt for t in step.try_this] + [f.caption for f in step.figures]


AUDIT_FIGURES = {kind.name: kind.audit for kind in FIGURE_KINDS if kind.audit != "off"}
"""Figure kinds that plot the energy audit of the frame, and the audit mode
(explorer.lpv.audit.AUDIT_MODES) each needs (``FigureKindDecl.audit``)."""


def uses_audit(step: Step) -> str:
    """The audit mode the step needs (a figure of :data:`AUDIT_FIGURES` or an ``audit.*``
    number, :func:`explorer.lessons.live_values.audit_needed`): the window asks the pipelines to
    measure that much while it shows; ``off`` when it quotes none."""
    from explorer.lpv.audit import strongest_audit

    return strongest_audit(
        *[AUDIT_FIGURES.get(spec.kind, "off") for spec in step.figures],
        *[live_values.audit_needed(name) for text in _texts(step)
          for name, _ in lesson_text.placeholders(text)])


def uses_truth(step: Step) -> bool:
    """The step quotes a number measured against Mitsuba (``error.mitsuba_*``,
    ``error.reference_mitsuba_*``)."""
    return any(name.startswith(("error.mitsuba_", "error.reference_mitsuba_"))
               for text in _texts(step) for name, _ in lesson_text.placeholders(text))


def uses_error(step: Step) -> bool:
    return any(name.startswith("error.") for text in _texts(step)
               for name, _ in lesson_text.placeholders(text))


def figure_context(state: AppState):
    """The figures' shared context (their interactive state), kept on the app state."""
    context = state.lesson_figures
    if context is None:
        from explorer.ui.figures import FigureContext

        context = FigureContext()
        state.lesson_figures = context
    return context


# --- the panel ---------------------------------------------------------------------------

def gui_article(state: AppState) -> None:
    session = session_of(state)
    sync_requested(state, session)
    if session.lesson is None:
        _lesson_list(state, session)
        return
    if not _header(state, session):
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


def _lesson_list(state: AppState, session: LessonSession) -> None:
    widgets.dim_text_wrapped("Each lesson is a short article. Its steps set the scene, the "
                             "settings and the view they talk about; the numbers in the text "
                             "are read from what is on screen, and every \"try this\" is a "
                             "button. Your own settings come back when you leave.")
    imgui.spacing()
    imgui.begin_child("contents", (0, -imgui.get_frame_height_with_spacing()))
    course = session.course()
    for title, lessons in list_sections(course):
        if title:
            imgui.separator_text(title)
        _list_entries(state, session, lessons)
        if not lessons:
            widgets.dim_text_wrapped("none yet: lpv-explorer lessons new NAME --dir "
                                     f"{course.folder} writes one to start from")
    imgui.end_child()
    for error in session.errors:
        imgui.text_colored(widgets.ERROR, f"broken: {error}")
    if imgui.small_button("Reload lessons"):
        session.reload_all()


def list_sections(course) -> list[tuple[str, list]]:
    """The lesson list's sections: (heading, lessons); one without a heading when only
    the shipped course is read, else the reader's folder (what they asked for, on top)
    and then the course."""
    own = [lesson for lesson in course.lessons if course.own(lesson)]
    shipped = [lesson for lesson in course.lessons if not course.own(lesson)]
    if course.folder is None:
        return [("", course.lessons)]
    mine = (f"Your lessons ({course.folder.name})", own)
    return [mine, ("The course", shipped)] if shipped else [mine]


def _list_entries(state: AppState, session: LessonSession, lessons: list) -> None:
    for lesson in lessons:
        imgui.push_id(str(lesson.path))
        if imgui.selectable(f"{lesson.number:02d}   {lesson.title}", False)[0]:
            session.open(lesson.id, resume=True)     # where the reader left it
            state.lesson_id = lesson.id
            show_screen(state, session.apply(current_screen(state)))
        imgui.indent(28.0)
        left_at = session.places.get(lesson.id, (1, 0.0))[0]
        where = f"; you left it at step {left_at}" if left_at > 1 else ""
        widgets.dim_text_wrapped(f"{lesson.summary} ({len(lesson.steps)} steps{where})")
        imgui.unindent(28.0)
        imgui.spacing()
        imgui.pop_id()


def _header(state: AppState, session: LessonSession) -> bool:
    """The lesson's title, step list and arrows, and its status line; False when the
    reader went back to the list (nothing of the lesson may be drawn after that)."""
    lesson, step = session.lesson, session.step
    if imgui.small_button("< All lessons"):
        restored = session.close()
        if restored is not None:
            show_screen(state, restored)
        state.lesson_id = None
        return False
    imgui.same_line()
    imgui.push_text_wrap_pos(0.0)     # a long title wraps beside the button (1280 px)
    imgui.text_colored(widgets.ACCENT, f"{lesson.number:02d}  {lesson.title}")
    imgui.pop_text_wrap_pos()
    changed = False
    imgui.begin_disabled(session.step_number <= 1)
    if imgui.arrow_button("##previous", imgui.Dir.left):
        changed = session.previous()
    imgui.end_disabled()
    imgui.same_line()
    imgui.set_next_item_width(max(imgui.get_content_region_avail().x - 30.0, 60.0))
    if imgui.begin_combo("##steps", f"Step {step.number} of {session.step_count}: "
                                    f"{step.title}"):
        for item in lesson.steps:
            if imgui.selectable(f"{item.number}. {item.title}", item.number == step.number)[0]:
                changed = session.go(item.number) or changed
        imgui.end_combo()
    imgui.same_line()
    imgui.begin_disabled(session.step_number >= session.step_count)
    if imgui.arrow_button("##next", imgui.Dir.right):
        changed = session.next()
    imgui.end_disabled()
    if changed:
        _goto(state, session)
    _status(state, session)
    if session.reload_error:          # the last save of the lesson's file did not load
        imgui.push_text_wrap_pos(0.0)
        imgui.text_colored(widgets.ERROR, f"Your last save is not shown: {session.reload_error}")
        imgui.pop_text_wrap_pos()
    return True


def _goto(state: AppState, session: LessonSession) -> None:
    """Show the step now selected (when lesson settings are on screen)."""
    if session.applied:
        show_screen(state, session.apply(current_screen(state)))


def _status(state: AppState, session: LessonSession) -> None:
    step = session.step
    if session.applied:
        if session.tried is not None:
            label, _ = try_label(step.try_this[session.tried - 1])
            imgui.text_colored(widgets.WARN, f"trying: {label}")
            imgui.same_line()
            if imgui.small_button("Undo"):
                show_screen(state, session.apply(current_screen(state)))
        elif shows_step(state.settings, step):
            imgui.text_disabled("showing this step's settings")
        else:
            imgui.text_colored(widgets.WARN, "you changed the step's settings")
            imgui.same_line()
            if imgui.small_button("Reset step"):
                show_screen(state, session.apply(current_screen(state)))
        imgui.same_line()
        if imgui.small_button("Leave lesson settings"):
            show_screen(state, session.leave())
        if hasattr(state, "reader_mode"):
            imgui.same_line()
            # the reader's mode shows the panels the step uses; the explorer mode all
            if imgui.small_button("All panels" if state.reader_mode else "Reader's mode"):
                state.reader_mode = not state.reader_mode
            if imgui.is_item_hovered():
                imgui.set_tooltip("Reader's mode: only the panels this step uses. "
                                  "All panels: the explorer's every tool (Windows menu too).")
    else:
        imgui.text_disabled("your own settings are on screen")
        imgui.same_line()
        if imgui.small_button("Back to the lesson" if session.left else "Show this step"):
            show_screen(state, session.apply(current_screen(state)))
        imgui.push_text_wrap_pos(0.0)
        imgui.text_colored(widgets.WARN, OWN_NUMBERS)
        imgui.pop_text_wrap_pos()


ON_SCREEN = "the frame on screen"
OWN_FRAME = "your own frame (your settings, not this step's)"
OWN_NUMBERS = "The numbers in the text are your own frame's, not this step's."
"""Said under the status line while the reader's own settings are on screen: the step's
live numbers are read from the reader's frame."""


def frame_words(session: LessonSession) -> str:
    """Where the step's live numbers are read: the step's frame, or the reader's own."""
    return ON_SCREEN if session.applied else OWN_FRAME


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
        _try_section(state, session, page, step)
    _next_step(state, session, width)
    imgui.end_group()


def try_context(state: AppState, session: LessonSession, index: int,
                base: live_values.LiveContext) -> tuple[live_values.LiveContext, str]:
    """What the ``index``-th try-this's prompt quotes, and where it comes from: the
    configuration the button sets (the right side of a before | after split). Its frame
    quantities are read once it is on screen; its errors come from the Error panel's
    cache, so a configuration measured once keeps its numbers."""
    from explorer.ui.panels.error import error_service

    step = session.step
    item = step.try_this[index - 1]
    own = session.saved if session.saved is not None else current_screen(state)
    after = item.apply(step_settings(step, own)).with_changes(
        width=state.settings.width, height=state.settings.height)
    active = session.applied and session.tried == index
    cached = error_service(state).result_for(after)
    error = cached.stats if cached is not None else None
    if active and not item.split:
        return replace(base, error=error), "the frame on screen"
    if active:
        result = state.runtime.frame.compare_result if state.comparing else None
        return (replace(base, settings=after, result=result, error=error),
                "the right half of the split view")
    return (replace(base, settings=after, result=None, error=error),
            "the configuration this button sets: press it to read the frame")


def pending_note(prompt: str, context: live_values.LiveContext, active: bool,
                 figure_ids: tuple[str, ...] = ()) -> str:
    """What the "…" of a try-this prompt stand for, in words ("" when every number of
    the prompt has a value): numbers of the configuration the button sets are read once
    it is pressed; once it is, an error waits for the Error panel's measurement and a
    frame quantity for the frame."""
    pending = [live_values.lookup(name, figure_ids, tuple(context.marks)).source
               for name, fmt in lesson_text.placeholders(prompt)
               if live_values.render(name, fmt, context, figure_ids) == live_values.PENDING]
    if not pending:
        return ""
    if not active:
        return "…: read once you press the button"
    if "error" in pending:
        return "…: the Error panel measures it against the reference, in the background"
    return "…: read from the next frame"


def _pending_audit(name: str, context: live_values.LiveContext,
                   figure_ids: tuple[str, ...]) -> str | None:
    """The reason an ``audit.*`` number waits for (its audit mode did not measure it),
    closing the tooltip's parenthesis; None for other numbers or no frame yet."""
    if not name.startswith("audit.") or context.result is None:
        return None
    reason = live_values.pending_reason(name, context, figure_ids)
    return None if reason is None else reason + ")"


PROVISIONAL = "≈"
"""Marks a number read from a frame that is still converging (the view says
"propagating k/N"): it changes until the frame has converged; its tooltip says so. (No
line of text announces it: the article would move under the reader's mouse each time a
try-this starts a new frame.)"""


def provisional(quantity) -> bool:
    """Whether ``quantity`` is read from the pipeline's frame (and so changes while it
    converges): frame and audit numbers; not settings, constants, the Error panel's
    measurement or a figure's own readout."""
    return quantity.source in ("frame", "audit") and not quantity.constant


def step_settings(step: Step, own):
    from explorer.ui.lesson_panel import step_screen

    return step_screen(step, own).settings


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
                else _pending_audit(name, source["context"], step.figure_ids)
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
        context_figures = figure_context(state)
        context_figures.update_from_app(state)
        draw_figure(replace(spec, caption=""), width, context_figures)
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


def _try_section(state: AppState, session: LessonSession, page: Page, step: Step) -> None:
    """Every try-this of the step: its button and its prompt, whose live numbers describe
    the configuration the button sets (:func:`try_context`)."""
    imgui.separator_text("Try this")
    source = page.env.source
    base = source["context"]
    frames, step_key = session.try_frames, (session.lesson.id, step.number)
    if session.applied and session.tried is None:
        frames.keep_step(step_key, base.result)
    for index, item in enumerate(step.try_this, start=1):
        context, where = try_context(state, session, index, base)
        key = (session.lesson.id, step.number, index)
        pressed = session.applied and session.tried == index
        if pressed and context.result is not None and \
                same_frame(context.result.settings, context.settings):
            frames.keep_after(key, context.result)
        elif not pressed:
            context = frames.after_context(key, context)
        source["context"], source["where"] = context, where
        if session.applied and session.tried == index and item.predict is not None:
            session.revealed.add(key)
        if item.predict is not None and key not in session.revealed:
            _prediction(session, page, item.predict, key)
            continue
        runs = (lesson_text.TryButton(index), lesson_text.Text(" ")) + \
            lesson_text.parse(item.prompt)[0].runs
        if item.predict is not None:
            runs += (lesson_text.Text(" " + verdict(item.predict, session.guesses.get(key)),
                                      "italic"),)
        note = pending_note(item.prompt, source["context"],
                            session.applied and session.tried == index, step.figure_ids)
        if note:       # in the same paragraph: it explains this prompt's "…"
            runs += (lesson_text.Text(f" ({note})", "italic"),)
        before = frames.before_note(step_key, item.prompt, base, step.figure_ids) \
            if key in frames.after else ""
        if before:     # the step's own numbers beside the press's, also after Undo
            runs += (lesson_text.Text(f" ({before})", "italic"),)
        page.draw((lesson_text.Paragraph(runs),))
    source["context"], source["where"] = base, frame_words(session)


def verdict(prediction, guess: int | None) -> str:
    """What the article says once a prediction's button was pressed."""
    right = prediction.choices[prediction.answer - 1]
    if guess is None:
        return f"(The answer: {right}.)"
    if guess == prediction.answer:
        return f"(You predicted {right}: right.)"
    return f"(You predicted {prediction.choices[guess - 1]}; the answer is {right}.)"


def _prediction(session: LessonSession, page: Page, prediction, key) -> None:
    """"Predict, then press": the question and its choices, then the button; the prompt
    stays hidden until the button is pressed."""
    index = key[2]
    page.draw((lesson_text.Paragraph((lesson_text.Text("Predict: ", "bold"),
                                      lesson_text.Text(prediction.question, "italic"))),))
    guess = session.guesses.get(key)
    for number, choice in enumerate(prediction.choices, start=1):
        if number > 1:
            imgui.same_line()
        if imgui.radio_button(f"{choice}##predict{index}", guess == number):
            session.guesses[key] = number
    runs = (lesson_text.TryButton(index), lesson_text.Text(" "),
            lesson_text.Text("then press to see what happens." if guess else
                             "make your guess, then press to see.", "italic"))
    page.draw((lesson_text.Paragraph(runs),))


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
            _goto(state, session)
    else:
        index = session.lessons.index(session.lesson) if session.lesson in session.lessons \
            else -1
        if 0 <= index < len(session.lessons) - 1:
            following: Lesson = session.lessons[index + 1]
            if _next_button("Next lesson", following.title, width):
                session.open(following.id)
                state.lesson_id = following.id
                _goto(state, session)
    imgui.dummy((width, 24))
