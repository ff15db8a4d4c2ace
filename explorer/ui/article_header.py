"""The article's header: the lesson's title, its step list and arrows, and the status line
that says whose settings are on screen."""

from __future__ import annotations

from typing import TYPE_CHECKING

from imgui_bundle import imgui

from explorer.ui import widgets
from explorer.ui.article_try import OWN_NUMBERS, try_label
from explorer.ui.lesson_panel import LessonSession, current_screen, show_screen, shows_step

if TYPE_CHECKING:
    from explorer.ui.state import AppState


def header(state: AppState, session: LessonSession) -> bool:
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
        goto_step(state, session)
    _status(state, session)
    if session.reload_error:          # the last save of the lesson's file did not load
        imgui.push_text_wrap_pos(0.0)
        imgui.text_colored(widgets.ERROR, f"Your last save is not shown: {session.reload_error}")
        imgui.pop_text_wrap_pos()
    return True


def goto_step(state: AppState, session: LessonSession) -> None:
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
