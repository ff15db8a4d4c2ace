"""The article's try-this section: each button's label, its prompt with the numbers of the
configuration it sets, and the predict-then-press questions."""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

from imgui_bundle import imgui

from explorer.lessons import TRY_GRIDS, Step, TryThis, live_values
from explorer.lessons import text as lesson_text
from explorer.lessons.words import for_reader
from explorer.ui.kept_answers import KeptAnswers
from explorer.ui.lesson_panel import LessonSession
from explorer.ui.textflow import Page
from explorer.ui.try_numbers import same_frame

if TYPE_CHECKING:
    from explorer.ui.state import AppState


ON_SCREEN = "the frame on screen"
OWN_FRAME = "your own frame (your settings, not this step's)"
OWN_NUMBERS = "The numbers in the text are your own frame's, not this step's."
"""Said under the status line while the reader's own settings are on screen: the step's
live numbers are read from the reader's frame."""


def frame_words(session: LessonSession) -> str:
    """Where the step's live numbers are read: the step's frame, or the reader's own."""
    return ON_SCREEN if session.applied else OWN_FRAME


COMPARE_WORDS = {"split": "the step left of the divider, the change right of it",
                 "difference": "their difference in false colour",
                 "side-by-side": "the step's whole view beside the changed one",
                 "small-multiples": "the step beside a view of each value"}
"""How a comparing try-this shows its change (``TryThis.compare``), in words."""
AFTER_SIDE = {"split": "the right half of the split view",
              "difference": "configuration B of the difference view",
              "side-by-side": "the right-hand view",
              "small-multiples": "view B, the first value"}
"""Where a comparing try-this's numbers are read while it is pressed."""


def try_label(item: TryThis) -> tuple[str, str]:
    """(button text, tooltip) of a try-this, in words (``TryThis.button``): the
    control's label and the value, its documentation as tooltip."""
    label, tip = item.button()
    tip = for_reader(tip)
    if item.compares:
        tip += f"\nShown as before | after: {COMPARE_WORDS[item.compare]}."
    return label, tip


def try_context(state: AppState, session: LessonSession, index: int,
                base: live_values.LiveContext) -> tuple[live_values.LiveContext, str]:
    """What the ``index``-th try-this's prompt quotes, and where it comes from: the
    configuration the button sets (the right side of a before | after split). Its frame
    quantities are read once it is on screen; its errors come from the Error panel's
    cache, so a configuration measured once keeps its numbers."""
    from explorer.ui.panels.error import error_service

    step = session.step
    item = step.try_this[index - 1]
    own = session.saved.settings if session.saved is not None else state.settings
    after = _after_settings(step, index, own, state.settings.width, state.settings.height)
    active = session.applied and session.tried == index
    cached = error_service(state).result_for(after)
    error = cached.stats if cached is not None else None
    if active and not item.compares:
        return replace(base, error=error), "the frame on screen"
    if active:
        result = state.runtime.frame.compare_result if state.comparing else None
        return (replace(base, settings=after, result=result, error=error),
                AFTER_SIDE[item.compare])
    return (replace(base, settings=after, result=None, error=error),
            "the configuration this button sets: press it to read the frame")


AFTER_KEPT = 256
_AFTER = KeptAnswers(most=AFTER_KEPT)
"""The settings each try-this sets: the article draws every try-this's prompt every
frame, from the same few settings."""


def _after_settings(step: Step, index: int, own, width: int, height: int):
    """The settings the ``index``-th try-this of ``step`` sets on the reader's own
    settings ``own`` at the view's size, made once while those stay the same objects
    (settings are frozen)."""
    return _AFTER.answer(
        (id(step), index), (step, own, width, height),
        lambda: step.try_this[index - 1].apply(step.settings(own)).with_changes(
            width=width, height=height))


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


def try_section(state: AppState, session: LessonSession, page: Page, step: Step) -> None:
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
        grid = item.compare in TRY_GRIDS        # the views render at their cells' size
        if pressed and context.result is not None and \
                same_frame(context.result.settings, context.settings, not grid):
            frames.keep_after(key, context.result, grid)
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
