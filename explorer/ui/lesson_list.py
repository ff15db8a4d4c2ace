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
    for title, lessons, broken in list_sections_with_errors(course):
        if title:
            imgui.separator_text(title)
        _list_entries(state, session, lessons)
        if not lessons and not broken:
            widgets.dim_text_wrapped("none yet: lpv-explorer lessons new NAME --dir "
                                     f"{course.folder} writes one to start from")
        # each broken file under its own section, wrapped: the whole line can be read
        imgui.push_text_wrap_pos(0.0)
        for error in broken:
            imgui.text_colored(widgets.ERROR, f"broken: {error}")
        imgui.pop_text_wrap_pos()
    imgui.end_child()
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


def list_sections_with_errors(course) -> list[tuple[str, list, list]]:
    """:func:`list_sections` with each section's broken files: (heading, lessons,
    errors), the folder's errors under the folder, the course's under the course."""
    sections = list_sections(course)
    mine = [e for e in course.errors
            if course.folder is not None and e.path.parent == course.folder]
    others = [e for e in course.errors if e not in mine]
    if course.folder is None:
        return [(title, lessons, others) for title, lessons in sections]
    return [(title, lessons, mine if index == 0 else others)
            for index, (title, lessons) in enumerate(sections)]


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
