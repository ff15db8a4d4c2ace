"""Lesson panel: read a lesson step by step and put each step's configuration on screen.

The panel follows the app's convention, ``gui_lesson(state: AppState)``. What it
remembers between frames (which lesson, which step, the reader's own configuration
saved while a lesson step is applied) lives in a :class:`LessonSession`, a plain object
with no imgui in it, so navigation and apply/leave/return are tested headlessly.

"Apply this step" saves the reader's configuration (settings of A and B, view mode) the
first time, then shows the step: its scene, settings and corrections on top of the
reader's own settings (window size, exposure and the like are kept), the compare preset
as configuration B for split/difference steps, the inspect source for RSM and grid views,
and the step's plot tab. "Leave lesson settings" restores the saved configuration and
"Back to the lesson" applies the step again.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from explorer.lessons import (
    COMPARE_VIEWS,
    Lesson,
    LessonError,
    Step,
    find_lesson,
    load_all,
    math_to_text,
)
from explorer.lpv.settings import Settings

INSPECT_VIEWS = ("rsm-position", "rsm-normal", "rsm-flux", "grid-slice", "geometry-volume")
"""Step views the app shows in its Inspect panel rather than in the main view."""
MAIN_VIEW_BUFFERS = ("final", "direct", "indirect", "albedo")
"""Step views the main view shows (``AppState.view_buffer``)."""


@dataclass(frozen=True)
class Screen:
    """The part of the app state a lesson step sets."""

    settings: Settings
    compare_settings: Settings
    view_mode: str                 # "single" | "split" | "difference"
    view_buffer: str = "final"     # what the main view shows: final | direct | indirect | albedo
    inspect_source: str | None = None
    plot: str | None = None


def step_screen(step: Step, own: Screen) -> Screen:
    """What ``step`` shows, built on the reader's own configuration ``own``.

    Scene, corrections, camera, light and the step's overrides come from the step; every
    other setting keeps the reader's value. The final/direct/indirect/albedo views pick the
    main view's buffer; RSM and grid views go to the Inspect panel."""
    settings = step.settings(own.settings)
    buffer = step.view if step.view in MAIN_VIEW_BUFFERS else "final"
    if step.view in COMPARE_VIEWS:
        compare = own.compare_settings.with_changes(corrections=step.compare)
        mode = step.view
    else:
        compare, mode = own.compare_settings, "single"
    return Screen(settings=settings, compare_settings=compare, view_mode=mode,
                  view_buffer=buffer,
                  inspect_source=step.view if step.view in INSPECT_VIEWS else None,
                  plot=step.plot)


def shows_step(settings: Settings, step: Step) -> bool:
    """Whether ``settings`` still has everything ``step`` sets (scene, corrections and
    the overridden fields); the app may fill in other fields, such as the camera."""
    return (settings.scene == step.scene and settings.corrections == step.corrections
            and all(getattr(settings, name) == value for name, value in step.overrides))


def step_caption(step: Step) -> str:
    """Where to look for this step, in words (shown above the step's text)."""
    if step.view in INSPECT_VIEWS:
        where = f"the {step.view} view in the Inspect panel"
    elif step.view in COMPARE_VIEWS:
        where = f"the {step.view} view: this step against the {step.compare_preset} preset"
    elif step.view == "final":
        where = "the final image"
    else:
        where = f"the {step.view} light"
    parts = [f"Look at {where}"]
    if step.plot:
        parts.append(f"the {step.plot} plot")
    return " and ".join(parts) + "."


@dataclass
class LessonSession:
    """Which lesson and step the reader is on, and the configuration to return to."""

    lessons: list[Lesson] = field(default_factory=list)
    errors: list[LessonError] = field(default_factory=list)
    lesson: Lesson | None = None
    step_number: int = 1
    saved: Screen | None = None
    """The reader's own configuration while lesson settings are applied, else None."""
    applied_step: tuple[str, int] | None = None
    """(lesson id, step) currently on screen, or None."""
    left: bool = False
    """The reader left the lesson's settings (and may go back to them)."""

    @classmethod
    def load(cls, directory=None) -> "LessonSession":
        """All lessons, their formula names checked against the derivation results
        generated from the registry (``explorer.derived``: a table, no sympy)."""
        lessons, errors = load_all(directory)
        return cls(lessons=lessons, errors=errors)

    @property
    def step(self) -> Step | None:
        return None if self.lesson is None else self.lesson.step(self.step_number)

    @property
    def step_count(self) -> int:
        return 0 if self.lesson is None else len(self.lesson.steps)

    @property
    def applied(self) -> bool:
        """True while a lesson step's configuration is on screen."""
        return self.saved is not None

    def open(self, key: str) -> Lesson:
        """Open the lesson with this id, number or file stem at its first step
        (KeyError lists the lessons)."""
        lesson = find_lesson(key, self.lessons)
        if self.lesson is None or lesson.id != self.lesson.id:
            self.lesson, self.step_number = lesson, 1
        return lesson

    def go(self, number: int) -> bool:
        """Move to step ``number``, clamped to the lesson; True when the step changed."""
        if self.lesson is None:
            return False
        number = max(1, min(number, self.step_count))
        changed = number != self.step_number
        self.step_number = number
        return changed

    def next(self) -> bool:
        return self.go(self.step_number + 1)

    def previous(self) -> bool:
        return self.go(self.step_number - 1)

    def apply(self, current: Screen) -> Screen:
        """The configuration for the current step; the first apply saves ``current`` as
        the reader's own configuration."""
        step = self.step
        if step is None:
            raise RuntimeError("no lesson is open")
        if self.saved is None:
            self.saved = current
        self.applied_step = (self.lesson.id, step.number)
        self.left = False
        return step_screen(step, self.saved)

    def leave(self) -> Screen | None:
        """Give the reader's own configuration back (None when nothing was applied)."""
        saved, self.saved, self.applied_step = self.saved, None, None
        self.left = saved is not None
        return saved

    def close(self) -> Screen | None:
        """Close the lesson, restoring the reader's configuration if a step was applied."""
        restored = self.leave()
        self.lesson, self.step_number, self.left = None, 1, False
        return restored


# --- imgui ---------------------------------------------------------------------------------

_SESSION_ATTRIBUTE = "lesson_session"


def session_of(state: Any) -> LessonSession:
    """The LessonSession kept on the app state (created and loaded on first use)."""
    session = getattr(state, _SESSION_ATTRIBUTE, None)
    if session is None:
        session = LessonSession.load()
        setattr(state, _SESSION_ATTRIBUTE, session)
    return session


def current_screen(state: Any) -> Screen:
    return Screen(settings=state.settings, compare_settings=state.compare_settings,
                  view_mode=state.view_mode,
                  view_buffer=getattr(state, "view_buffer", "final"))


def show_screen(state: Any, screen: Screen) -> None:
    """Put ``screen`` into the app state (settings of A and B, view mode and buffer,
    inspect source, plot tab)."""
    state.settings = screen.settings
    state.compare_settings = screen.compare_settings
    state.view_mode = screen.view_mode
    if hasattr(state, "view_buffer"):
        state.view_buffer = screen.view_buffer
    if screen.inspect_source is not None and hasattr(state, "inspect"):
        state.inspect.source = screen.inspect_source
    if screen.plot is not None and hasattr(state, "plot_tab"):
        state.plot_tab = screen.plot


def sync_requested_lesson(state: Any, session: LessonSession) -> None:
    """Follow ``state.lesson_id`` (set by ``run --lesson ID``) and apply its first step."""
    wanted = getattr(state, "lesson_id", None)
    if not wanted:
        return
    if session.lesson is not None and wanted in (session.lesson.id, session.lesson.path.stem):
        return
    try:
        session.open(wanted)
    except KeyError as exc:
        state.lesson_id = None
        if hasattr(state, "notify"):
            state.notify(str(exc.args[0]), "error")
        return
    state.lesson_id = session.lesson.id
    show_screen(state, session.apply(current_screen(state)))


def gui_lesson(state: Any) -> None:
    """The Lessons panel."""
    from imgui_bundle import imgui

    session = session_of(state)
    sync_requested_lesson(state, session)
    if session.lesson is None:
        _lesson_list(state, session, imgui)
        return
    lesson, step = session.lesson, session.step
    if imgui.small_button("< Lessons"):
        restored = session.close()
        if restored is not None:
            show_screen(state, restored)
        state.lesson_id = None
        return
    imgui.same_line()
    imgui.text_colored(imgui.ImVec4(0.33, 0.62, 0.98, 1.0), lesson.title)

    # navigation: previous / step list / next
    changed = False
    imgui.begin_disabled(session.step_number <= 1)
    if imgui.arrow_button("##previous", imgui.Dir.left):
        changed = session.previous()
    imgui.end_disabled()
    imgui.same_line()
    imgui.set_next_item_width(max(imgui.get_content_region_avail().x - 30.0, 60.0))
    if imgui.begin_combo("##steps", f"{step.number}/{session.step_count}  {step.title}"):
        for item in lesson.steps:
            if imgui.selectable(f"{item.number}. {item.title}",
                                item.number == step.number)[0]:
                changed = session.go(item.number) or changed
        imgui.end_combo()
    imgui.same_line()
    imgui.begin_disabled(session.step_number >= session.step_count)
    if imgui.arrow_button("##next", imgui.Dir.right):
        changed = session.next()
    imgui.end_disabled()
    step = session.step
    if changed and session.applied:
        show_screen(state, session.apply(current_screen(state)))

    # apply / leave / return
    # "on screen" until the reader changes something the step set
    on_screen = (session.applied_step == (lesson.id, step.number)
                 and session.saved is not None
                 and shows_step(state.settings, step))
    if session.applied:
        if on_screen:
            imgui.text_disabled("showing this step")
        elif imgui.button("Apply this step"):
            show_screen(state, session.apply(current_screen(state)))
        imgui.same_line()
        if imgui.button("Leave lesson settings"):
            show_screen(state, session.leave())
    else:
        if imgui.button("Back to the lesson" if session.left else "Apply this step"):
            show_screen(state, session.apply(current_screen(state)))
    imgui.separator()

    imgui.push_style_color(imgui.Col_.text, imgui.ImVec4(0.62, 0.64, 0.68, 1.0))
    imgui.text_wrapped(step_caption(step))
    imgui.pop_style_color()
    _markdown(state, step.text, imgui)
    if step.formulas:
        imgui.separator_text("Formulas")
        _formulas(state, step, imgui)
    if step.try_this:
        imgui.separator_text("Try this")
        for item in step.try_this:
            imgui.bullet()
            imgui.same_line()
            imgui.text_colored(imgui.ImVec4(1.0, 0.75, 0.3, 1.0), item.control)
            imgui.text_wrapped(item.prompt)


def _lesson_list(state: Any, session: LessonSession, imgui) -> None:
    imgui.text_wrapped("Pick a lesson. Each step sets the scene, settings and view it talks "
                       "about; your own settings come back when you leave.")
    for lesson in session.lessons:
        if imgui.selectable(f"{lesson.number:02d}  {lesson.title}", False)[0]:
            session.open(lesson.id)
            state.lesson_id = lesson.id
            show_screen(state, session.apply(current_screen(state)))
        if imgui.is_item_hovered():
            imgui.set_tooltip(f"{lesson.summary}\n({len(lesson.steps)} steps)")
    for error in session.errors:
        imgui.text_colored(imgui.ImVec4(1.0, 0.42, 0.38, 1.0), f"broken: {error}")
    if imgui.small_button("Reload lessons"):
        fresh = LessonSession.load()
        session.lessons, session.errors = fresh.lessons, fresh.errors


def _markdown(state: Any, text: str, imgui) -> None:
    """Step text through imgui_md (``rich_md``) when the app made a markdown context
    (``state.runtime.markdown_ready``), with inline math turned into text the window's
    font can draw; wrapped plain paragraphs otherwise."""
    text = math_to_text(text)
    if getattr(getattr(state, "runtime", None), "markdown_ready", False):
        from imgui_bundle import imgui_md

        imgui_md.render_unindented(text)
        return
    for block in markdown_blocks(text):
        imgui.text_wrapped(block)
        imgui.spacing()


def markdown_blocks(text: str) -> list[str]:
    """Paragraphs and list items of ``text`` with hard line breaks joined and the
    ``**bold**`` markers removed (the plain-text fallback of the panel)."""
    blocks: list[str] = []
    current: list[str] = []

    def flush() -> None:
        if current:
            blocks.append(" ".join(current).replace("**", ""))
            current.clear()

    for line in text.strip().splitlines():
        stripped = line.strip()
        if not stripped:
            flush()
        elif stripped.startswith("* ") or (stripped.split(" ", 1)[0].rstrip(".").isdigit()
                                          and stripped.split(" ", 1)[0].endswith(".")):
            flush()
            current.append(stripped)
        else:
            current.append(stripped)
    flush()
    return blocks


def _formulas(state: Any, step: Step, imgui) -> None:
    """The step's formulas, typeset from the generated derivation table (no sympy)."""
    from explorer import derived
    from explorer.ui import widgets

    formulas = getattr(getattr(state, "runtime", None), "formulas", None)
    for name in step.formulas:
        try:
            result = derived.get(name)
        except KeyError:
            imgui.text_disabled(f"{name} (not in the registry)")
            continue
        widgets.formula(formulas, result.latex, tooltip=result.tooltip)
        imgui.text_disabled(result.statement)
