"""Write a lesson step as the window shows it (article column, 3D view, panels) to a PNG,
from a window that needs no display (glfw's null platform with EGL, as the rest of the
headless pipeline): ``lpv-explorer lessons --export ID --step K --out step.png``.

The window draws frames until the step's frame has converged and its typeset text
and figures are on screen; a step that quotes measured errors (``{{error.*}}``) also
waits for the Error panel's measurement, up to ``wait_s`` seconds.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

SETTLE_FRAMES = 4
"""Frames drawn after everything is ready (layout, textures uploaded in the last one)."""


@dataclass(frozen=True)
class ExportedStep:
    """A written step: the PNG and where the 3D view's image lies in it."""

    path: Path
    view_rect: tuple[int, int, int, int] | None
    """(x0, y0, x1, y1) pixels of the PNG (row 0 at the top) the view's image covers."""


def exported_lesson(lesson_id: str, step: int, try_this: int | None = None,
                    lessons_dir: Path | None = None):
    """The lesson :func:`export_step` would export (explorer.lessons.model.Lesson), read
    without opening a window; KeyError/IndexError for a lesson, step or try-this that does
    not exist."""
    from explorer.lessons.folder import load_course

    lesson = load_course(lessons_dir, shipped=False).find(lesson_id)
    wanted = lesson.step(step)
    if try_this is not None and not 1 <= try_this <= len(wanted.try_this):
        raise IndexError(f"step {step} of {lesson.id} has try-this 1..{len(wanted.try_this)}"
                         f", not {try_this}")
    return lesson


def export_step(lesson_id: str, step: int, out: Path, width: int = 1600, height: int = 900,
                wait_s: float = 600.0, try_this: int | None = None,
                overlays: bool = True, headless: bool | None = None,
                lessons_dir: Path | None = None) -> ExportedStep:
    """Open a hidden window at ``lesson_id`` step ``step`` (with its ``try_this``-th
    button pressed, 1-based, when given), draw until the step is ready, write the window
    to ``out``. ``overlays`` False: the step without the in-scene overlays its
    ``[steps.show]`` table sets (what the main view shows without them). Raises
    WindowError without a display, KeyError/IndexError for a lesson, step or try-this that
    does not exist, TimeoutError when the frame never comes. ``headless``: draw without
    a display (glfw's null platform with EGL; default: whenever this glfw has it);
    ``lessons_dir``: a folder of lessons read instead of the shipped ones."""
    from explorer.gl.window import headless_available
    from explorer.ui.app import App, write_png
    from explorer.ui.article_numbers import uses_error, uses_truth
    from explorer.ui.panels.error import error_service
    from explorer.ui.state import AppState, OverlayState
    from explorer.ui.window_options import WindowOptions

    if headless is None:
        headless = headless_available()
    lesson = exported_lesson(lesson_id, step, try_this, lessons_dir)
    wanted = lesson.step(step)
    state = AppState(lesson_id=lesson.id, lesson_step=step,
                     lesson_folder=None if lessons_dir is None else str(lessons_dir),
                     lesson_folder_alone=True)
    app = App(state, WindowOptions(width=width, height=height, visible=False, vsync=False,
                                   persist_settings=False, headless=headless))
    try:
        start = time.monotonic()
        ready_at = None
        frames = 0
        pressed = try_this is None
        while True:
            app.frame()
            frames += 1
            rt = app.state.runtime
            if not overlays and app.state.overlays.any_shown:
                app.state.overlays = OverlayState()     # the step as if it showed none
            if not pressed and frames == SETTLE_FRAMES:
                from explorer.ui.lesson_panel import current_screen, show_screen

                session = app.state.lesson_session
                show_screen(app.state, session.toggle_try(try_this, current_screen(app.state)))
                pressed = True
            # nothing left to do, and nothing the panels changed in the frame just drawn
            converged = (app.status is not None and not app.status.active
                         and not app.drew_change)
            ready = (rt.frame.result is not None and frames > SETTLE_FRAMES and pressed
                     and converged
                     and (not app.state.comparing or rt.frame.compare_result is not None))
            if ready and uses_error(wanted):
                service = error_service(app.state)
                service.lesson_wants = True
                ready = service.result_for() is not None or service.problem is not None
                if ready and uses_truth(wanted) and service.against_mitsuba:
                    ready = service.truth_for() is not None or bool(service.truth_problem)
            if ready:
                ready_at = frames if ready_at is None else ready_at
                if frames - ready_at >= SETTLE_FRAMES:
                    break
            if time.monotonic() - start > wait_s:
                raise TimeoutError(f"lesson {lesson.id} step {step} was not ready after "
                                   f"{wait_s:g} s")
        app.frame(capture=True)
        write_png(app.last_pixels, out)
        rect = app.state.runtime.view.view_rect
    finally:
        app.close()
    return ExportedStep(Path(out), None if rect is None else tuple(int(round(v))
                                                                     for v in rect))
