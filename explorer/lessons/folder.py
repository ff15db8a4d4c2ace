"""A course to read: the shipped lessons, a folder of one's own (a teacher's), or both
side by side, as every command and the window read them (``--lessons DIR``).

A folder's lessons keep their own numbers; a lesson of the folder whose id the shipped
course already uses is reported as broken (one id names one lesson), and a key given to
:meth:`Course.find` is looked up in the folder first, so ``--lesson 01 --lessons DIR``
opens the folder's first lesson, not the shipped one.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from explorer.lessons.model import Lesson, LessonError
from explorer.lessons.reader import find_lesson, load_all
from explorer.resources import lesson_dir


@dataclass
class Course:
    """Lessons in the order the window lists them (the shipped course, then the
    folder's), the errors of those that did not load, and the folder (None: shipped
    only)."""

    lessons: list[Lesson] = field(default_factory=list)
    errors: list[LessonError] = field(default_factory=list)
    folder: Path | None = None

    def own(self, lesson: Lesson) -> bool:
        """Whether ``lesson`` comes from the folder (not the shipped course)."""
        return self.folder is not None and lesson.path.parent == self.folder

    def find(self, key: str) -> Lesson:
        """The lesson ``key`` names (:func:`find_lesson`), the folder's first."""
        ordered = sorted(self.lessons, key=lambda lesson: not self.own(lesson))
        return find_lesson(key, ordered, self.errors)


def load_course(folder: Path | str | None = None, shipped: bool = True,
                **load_options) -> Course:
    """The shipped lessons (``folder`` None), the ``folder``'s alone (``shipped``
    False), or both; ``load_options``: :func:`load_all`'s (``check_formula``)."""
    if folder is None:
        lessons, errors = load_all(None, **load_options)
        return Course(lessons, errors)
    folder = Path(folder).expanduser().resolve()
    own, errors = load_all(folder, **load_options)
    if not shipped or folder == lesson_dir().resolve():
        return Course(own, errors, folder)
    course, course_errors = load_all(None, **load_options)
    taken = {lesson.id: lesson.path for lesson in course}
    kept = []
    for lesson in own:
        if lesson.id in taken:
            errors.append(LessonError(lesson.path, f"id {lesson.id!r} is the shipped lesson "
                                      f"{taken[lesson.id].name}'s; give this one its own id",
                                      field="id"))
        else:
            kept.append(lesson)
    return Course(course + kept, course_errors + errors, folder)
