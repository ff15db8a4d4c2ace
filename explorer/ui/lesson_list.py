"""The Lesson panel's contents: the lessons of the course and of the reader's folder, each
with its summary and where the reader left it."""

from __future__ import annotations

from typing import TYPE_CHECKING

from imgui_bundle import imgui

from explorer.ui import widgets
from explorer.ui.lesson_panel import LessonSession, current_screen, show_screen

if TYPE_CHECKING:
    from explorer.ui.state import AppState


def lesson_list(state: AppState, session: LessonSession) -> None:
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
