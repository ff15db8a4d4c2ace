"""The file of the lesson being read, watched like the shaders and the scene files
(explorer/ui/scene_watch.py): a lesson saved while the window shows it is read again and
shown at the same step (the last one if the edit removed steps), its settings applied
again when the step's were on screen; an edit that does not load keeps the lesson as it
was, with the one-line error (file:line, step, key) in Messages. While the lesson list
shows, the reader's folder is watched: a lesson saved, added or removed there is listed
anew.

The controller calls :meth:`LessonWatch.poll` every ``SHADER_POLL_S``, with the shaders
and the scene; the lesson's stamps are its file's modification time and size, so an
editor's save in place or by rename counts."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from explorer.ui.scene_watch import SceneWatch

if TYPE_CHECKING:
    from explorer.ui.state import AppState


@dataclass
class LessonWatch:
    """The lesson file shown and its stamp."""

    files: SceneWatch = field(default_factory=SceneWatch)

    def poll(self, state: AppState) -> bool:
        """Read the open lesson again if its file changed; True when the window shows
        the edit."""
        session = state.lesson_session
        if session is None:
            return False
        if session.lesson is None:
            return self._poll_folder(state, session)
        path = str(session.lesson.path)
        if self.files.name != path:
            self.files.watch(path, (path,))
            return False
        if not self.files.changed():
            return False
        return reload_lesson(state, session)

    def _poll_folder(self, state: AppState, session) -> bool:
        """While the list shows, the reader's folder: a lesson saved, added or removed
        there reads the lessons again (the list then shows it, or its error)."""
        if session.folder is None:
            return False
        key = f"folder {session.folder}"
        try:
            files = tuple(sorted(str(path) for path in session.folder.glob("*.toml")))
        except OSError:
            return False
        if self.files.name != key or self.files.files != files:
            first = self.files.name != key
            self.files.watch(key, files)
            if first:
                return False
        elif not self.files.changed():
            return False
        session.reload_all()
        state.notify(f"{session.folder.name}: lessons read again")
        return True


def reload_lesson(state: AppState, session) -> bool:
    """Read ``session``'s open lesson from its file and show it at the same step; False
    (and the reason in one line) when the file no longer makes a lesson."""
    from explorer.lessons import LessonError, load_lesson
    from explorer.ui.lesson_panel import current_screen, show_screen

    path = session.lesson.path
    try:
        edited = load_lesson(path)
    except LessonError as exc:
        return _refused(state, session, str(exc))
    other = next((lesson for lesson in session.lessons
                  if lesson.id == edited.id and lesson.path != path), None)
    if other is not None:
        return _refused(state, session, f"{path}, field 'id': {edited.id!r} is "
                                        f"{other.path.name}'s already")
    tried = session.tried
    session.replace_lesson(edited)
    if state.lesson_id is not None:
        state.lesson_id = edited.id
    if session.applied:
        step = session.step
        current = current_screen(state)
        if tried is not None and tried <= len(step.try_this):
            show_screen(state, session.apply_try(tried, current))
        else:
            show_screen(state, session.apply(current))
    state.notify(f"{path.name} changed on disk: reloaded at step {session.step_number}")
    return True


def _refused(state: AppState, session, reason: str) -> bool:
    """A save that does not load: said in Messages and above the article, in one line."""
    session.reload_error = reason
    state.notify(f"{reason} (the lesson on screen is the one read before)", "error")
    return False
