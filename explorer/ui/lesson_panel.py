"""Lesson state: which lesson and step is read, and what each step puts on screen.

The Lesson panel (``explorer/ui/article.py``, ``gui_article(state)``) draws the article;
what it remembers between frames (which lesson, which step, the reader's own
configuration saved while a lesson step is applied, the try-this on screen) lives in a
:class:`LessonSession`, a plain object with no imgui in it, so navigation,
apply/try/leave/return are tested headlessly.

"Apply this step" saves the reader's configuration (settings of A and B, view mode, the
in-scene overlays) the first time, then shows the step: its scene, settings and
corrections on top of the reader's own settings (window size, exposure and the like are
kept), the compare preset as configuration B for split/difference steps, the overlays its
``[steps.show]`` table sets (nothing else drawn or picked), the inspect source for RSM and
grid views, and the step's plot tab. "Leave lesson settings" restores the saved
configuration and "Back to the lesson" applies the step again. Overlays the reader turns
on while a step is shown stay through its try-this buttons (they change settings, not
what is drawn) until the step changes.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING

from explorer.lessons import (
    COMPARE_VIEWS,
    Lesson,
    LessonError,
    Step,
)
from explorer.lessons.folder import Course, load_course
from explorer.lpv.settings import Settings
from explorer.overlay_params import OverlayState
from explorer.ui.try_numbers import TryFrames

if TYPE_CHECKING:
    from explorer.ui.state import AppState

INSPECT_VIEWS = ("rsm-position", "rsm-normal", "rsm-flux", "grid-slice", "geometry-volume",
                 "cascade-weights")
"""Step views the app shows in its Inspect panel rather than in the main view."""
NOT_IN_SCENE_VIEWS = ("cascade-weights",)
"""Inspect views no in-scene overlay repeats (the cascade boxes outline the cascades; the
weights say which one each pixel reads): a step that draws overlays and names one of these
still brings the Inspect panel forward and says so."""
MAIN_VIEW_BUFFERS = ("final", "direct", "indirect", "albedo")
"""Step views the main view shows (``AppState.view_buffer``)."""


@dataclass(frozen=True)
class Screen:
    """The part of the app state a lesson step sets."""

    settings: Settings
    compare_settings: Settings
    view_mode: str                 # "single" or one of state.COMPARE_MODES
    view_buffer: str = "final"     # what the main view shows: final | direct | indirect | albedo
    inspect_source: str | None = None
    plot: str | None = None
    compare_overrides: tuple = ()
    """Fields (other than the corrections) in which configuration B differs from A: a
    try-this shown as before | after."""
    compare_variants: tuple = ()
    """The third and later views of small multiples: per view, the (field, value) pairs
    in which it differs from A (corrections included)."""
    overlays: OverlayState | None = None
    """What the main view draws in the scene (a private copy; None: not part of this
    screen, the window's overlays stay as they are)."""
    split_position: float | None = None
    """Where the split view's divider stands (a fraction of the view's width) when the
    step says; None: where the reader left it."""


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
                  plot=step.plot, overlays=step.overlays(own.overlays),
                  split_position=step.split_at)


def try_screen(step: Step, index: int, own: Screen) -> Screen:
    """What the step shows with its ``index``-th (1-based) try-this applied: the change
    on top of the step, or, when the try-this compares (``TryThis.compare``), the step
    (A, before) against the step with the change (B, after; for small multiples B and
    the further views each show one of its values) in the view mode it names."""
    item = step.try_this[index - 1]
    screen = step_screen(step, own)
    if not item.compares:
        return replace(screen, settings=item.apply(screen.settings))
    before = screen.settings
    after, *more = (item.apply(before, value) for value in item.variants)
    compare = screen.compare_settings.with_changes(corrections=after.corrections)
    return replace(screen, compare_settings=compare, view_mode=item.compare,
                   compare_overrides=_differences(before, after, with_corrections=False),
                   compare_variants=tuple(_differences(before, other) for other in more))


def _differences(before: Settings, after: Settings, with_corrections: bool = True
                 ) -> tuple[tuple[str, object], ...]:
    """The (field, value) pairs of ``after`` that differ from ``before``."""
    return tuple((name, getattr(after, name)) for name in _settings_fields()
                 if (with_corrections or name != "corrections")
                 and getattr(after, name) != getattr(before, name))


def _settings_fields() -> tuple[str, ...]:
    from dataclasses import fields

    return tuple(f.name for f in fields(Settings))


def shows_step(settings: Settings, step: Step) -> bool:
    """Whether ``settings`` still has everything ``step`` sets (scene, corrections and
    the overridden fields); the app may fill in other fields, such as the camera."""
    return (settings.scene == step.scene and settings.corrections == step.corrections
            and all(getattr(settings, name) == value for name, value in step.overrides))


READER_PANELS = ("View", "Lesson")
"""Panels the reader's mode always shows: the article and the 3D view it talks about."""
_LIGHT_CONTROLS = ("light", "lights", "light_flux", "object_transforms")


def step_panels(step: Step) -> frozenset[str]:
    """The panels ``step`` uses (the reader's mode shows these alone): the article and the
    view, the plot it names, the Inspect panel for a buffer the scene cannot show, the
    Show in scene panel when it draws in the scene, the Error panel when it quotes an
    error, the Corrections panel when it typesets or switches a correction, the Lights &
    objects or Scene panel when a try-this moves a light, an object or the scene."""
    from explorer.lessons.text import placeholders

    used = set(READER_PANELS)
    texts = [step.text] + [item.prompt for item in step.try_this]
    controls = step.controls()
    if step.plot is not None:
        used.add("Plots")
    if step.view in INSPECT_VIEWS and not step.show or step.view in NOT_IN_SCENE_VIEWS:
        used.add("Inspect")
    if step.show:
        used.add("Show in scene")
    if step.plot == "error" or any(name.startswith("error.") for text in texts
                                   for name, _ in placeholders(text)):
        used.add("Error")
    if any(c.startswith("corrections") for c in controls) or any(
            f.startswith("corrections.") for f in step.formulas):
        used.add("Corrections")
    if any(c in _LIGHT_CONTROLS for c in controls):
        used.add("Lights & objects")
    if "scene" in controls:
        used.add("Scene")
    return frozenset(used)


def hidden_panels(state, titles: Iterable[str]) -> frozenset[str]:
    """Of the panels ``titles`` (the window's, explorer.ui.layout.PANELS), those the
    reader's mode hides now: the ones the lesson step on screen does not use (none in the
    explorer mode, or when no lesson step is applied)."""
    if not state.reader_mode:
        return frozenset()
    session = state.lesson_session
    step = None if session is None or not session.applied else session.step
    if step is None:
        return frozenset()
    used = step_panels(step)
    return frozenset(title for title in titles if title not in used)


def step_caption(step: Step) -> str:
    """Where to look for this step, in words (shown above the step's text): the main
    view and what it draws in the scene when the step shows overlays, else the step's
    view (an Inspect source, the split or difference view, a buffer)."""
    drawn = overlay_words(step.overlays())
    if drawn and step.view in NOT_IN_SCENE_VIEWS:
        where = f"the main view ({drawn}), the {step.view} view in the Inspect panel"
    elif drawn:
        where = f"the main view ({drawn})"
    elif step.view in INSPECT_VIEWS:
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


_SLICE_WORDS = {"intensity": "the accumulated intensity", "flux": "the accumulated flux per cell",
                "in-flight": "the light in flight after step {t}"}
_INJECTED_WORDS = "the injected light, before any step"


def overlay_words(overlays: OverlayState) -> str:
    """What ``overlays`` draw in the scene, in words ("" when nothing is drawn)."""
    o, parts = overlays, []
    if o.slice:
        what = _SLICE_WORDS.get(o.slice_quantity, f"SH coefficient {o.slice_quantity[2:]}")
        if o.slice_quantity == "in-flight" and o.slice_step == 0:
            what = _INJECTED_WORDS
        parts.append(f"a {o.slice_axis} slice through the grid showing "
                     + what.format(t=o.slice_step))
    if o.glyphs:
        parts.append("SH glyphs " + ("around the picked cell" if o.glyph_cells == "picked"
                                     else "on the slice" if o.slice
                                     else f"on one {o.slice_axis} layer of cells"))
    if o.vpls:
        parts.append("the VPLs as discs")
    if o.blockers:
        parts.append("the geometry volume's blockers")
    if o.lattice:
        parts.append("the cell lattice")
    if o.cascade_boxes:
        parts.append("every cascade's extent")
    if o.picked_kind != "none" and not (o.glyphs and o.glyph_cells == "picked"):
        parts.append(f"a picked {o.picked_kind} (Picked panel)")
    if len(parts) > 1:
        return ", ".join(parts[:-1]) + " and " + parts[-1]
    return parts[0] if parts else ""


RESUME_FRAMES = 4
"""Frames over which a resumed lesson's article scrolls back to where it was left."""


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
    tried: int | None = None
    """The try-this (1-based) whose change is on screen, or None."""
    places: dict[str, tuple[int, float]] = field(default_factory=dict)
    """Lesson id -> (step, article scroll in pixels) where the reader left it for the
    list: opening it from the list again comes back there."""
    scroll: float = 0.0
    """The article's scroll offset as last drawn (the panel keeps it up to date)."""
    shown: tuple[str, int] | None = None
    """(lesson id, step) the article showed last: another one opens at its top."""
    _open_scroll: float = 0.0
    """The scroll :meth:`open` chose for the lesson it opened (0: its top)."""
    resume_frames: int = 0
    """Frames the panel still scrolls the article to :attr:`scroll` (a resumed lesson:
    its text's height is known only once it was drawn)."""
    guesses: dict[tuple[str, int, int], int] = field(default_factory=dict)
    """(lesson id, step, try-this) -> the reader's guess (1-based) of a prediction."""
    revealed: set[tuple[str, int, int]] = field(default_factory=set)
    """Predictions whose try-this the reader pressed: their answer is shown."""
    glossary: tuple | None = None
    """The lessons' glossary terms as the article read them (once, on first use); () when
    the glossary is missing or broken; None: not read yet."""
    try_frames: TryFrames = field(default_factory=TryFrames)
    """The frames each try-this's prompt quotes, before and after its press
    (explorer/ui/try_numbers.py): its numbers stay after Undo."""

    folder: Path | None = None
    """The reader's own lesson folder (``run --lessons DIR``), or None."""
    reload_error: str | None = None
    """Why the last save of the open lesson's file does not load (the lesson shown is the
    one read before), until a save loads or another lesson opens."""
    shipped: bool = True
    """Whether the shipped course is listed (besides the folder)."""

    @classmethod
    def load(cls, folder: Path | str | None = None, shipped: bool = True) -> LessonSession:
        """The shipped lessons and those of ``folder`` (or the folder's alone, ``shipped``
        False), their formula names checked against the derivation results generated from
        the registry (``explorer.derived``: a table, no sympy)."""
        course = load_course(folder, shipped)
        return cls(lessons=course.lessons, errors=course.errors, folder=course.folder,
                   shipped=shipped)

    def reload_all(self) -> None:
        """Read every lesson again (the list's "Reload lessons")."""
        fresh = LessonSession.load(self.folder, self.shipped)
        self.lessons, self.errors = fresh.lessons, fresh.errors

    def course(self) -> Course:
        return Course(self.lessons, self.errors, self.folder)

    def replace_lesson(self, edited: Lesson) -> None:
        """``edited`` (the open lesson read again from its file) in place of the lesson of
        that file; the reader stays at the same step (the last one if it has fewer)."""
        self.reload_error = None
        self.lessons = [edited if lesson.path == edited.path else lesson
                        for lesson in self.lessons]
        self.errors = [error for error in self.errors if error.path != edited.path]
        if self.lesson is not None and self.lesson.path == edited.path:
            self.lesson = edited
            self.step_number = max(1, min(self.step_number, len(edited.steps)))
            if self.applied_step is not None:
                self.applied_step = (edited.id, self.step_number)
            if self.shown is not None:
                self.shown = (edited.id, self.step_number)

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

    def open(self, key: str, resume: bool = False) -> Lesson:
        """Open the lesson with this id, number or file stem (KeyError lists the
        lessons) at its first step, or with ``resume`` where the reader left it for the
        list (its step; :meth:`opening_scroll` its scroll)."""
        lesson = self.course().find(key)
        if self.lesson is None or lesson.id != self.lesson.id:
            self.reload_error = None
            step, scroll = self.places.get(lesson.id, (1, 0.0)) if resume else (1, 0.0)
            self.lesson, self.step_number = lesson, max(1, min(step, len(lesson.steps)))
            self.scroll = self._open_scroll = scroll
            self.shown = None
        return lesson

    def opening_scroll(self) -> float | None:
        """Where the article should scroll to as it is drawn now: its top for a step it
        did not show last (a step or lesson change), the remembered offset for a lesson
        resumed from the list; None when it stays as the reader scrolled it."""
        if self.lesson is None:
            return None
        where = (self.lesson.id, self.step_number)
        if self.shown == where:
            return None
        scroll = self._open_scroll if self.shown is None else 0.0
        self._open_scroll = 0.0
        self.shown, self.scroll = where, scroll
        self.resume_frames = RESUME_FRAMES if scroll > 0 else 0
        return scroll

    def keep_scroll(self, scroll: float) -> None:
        """The article's scroll as just drawn, kept for :meth:`close`: only while it
        showed the step that is current (a click in it may have changed the step)."""
        if self.lesson is not None and self.shown == (self.lesson.id, self.step_number):
            self.scroll = scroll

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
        the reader's own configuration. Applied again while the step is on screen (a
        try-this undone), the overlays on screen stay."""
        step = self.step
        if step is None:
            raise RuntimeError("no lesson is open")
        if self.saved is None:
            self.saved = _own_copy(current)
        same = self.applied_step == (self.lesson.id, step.number)
        self.applied_step = (self.lesson.id, step.number)
        self.left = False
        self.tried = None
        return _keep_overlays(step_screen(step, self.saved), current, same)

    def apply_try(self, index: int, current: Screen) -> Screen:
        """The step with its ``index``-th try-this applied (the step is applied first if
        it was not; the reader's own configuration stays saved for leaving)."""
        step = self.step
        if step is None:
            raise RuntimeError("no lesson is open")
        if not 1 <= index <= len(step.try_this):
            raise IndexError(f"step {step.number} has try-this 1..{len(step.try_this)}, "
                             f"not {index}")
        same = self.applied_step == (self.lesson.id, step.number)
        self.apply(current)
        self.tried = index
        return _keep_overlays(try_screen(step, index, self.saved), current, same)

    def toggle_try(self, index: int, current: Screen) -> Screen:
        """One click on a try-this button: apply it, or undo it when it is on screen."""
        if self.tried == index and self.applied:
            return self.apply(current)
        return self.apply_try(index, current)

    def leave(self) -> Screen | None:
        """Give the reader's own configuration back (None when nothing was applied)."""
        saved, self.saved, self.applied_step = self.saved, None, None
        self.left = saved is not None
        self.tried = None
        return saved

    def close(self) -> Screen | None:
        """Close the lesson (remembering its step and scroll for :meth:`open` with
        ``resume``), restoring the reader's configuration if a step was applied."""
        if self.lesson is not None:
            drawn = self.shown == (self.lesson.id, self.step_number)
            self.places[self.lesson.id] = (self.step_number, self.scroll if drawn else 0.0)
        restored = self.leave()
        self.lesson, self.step_number, self.left = None, 1, False
        self.shown, self.scroll = None, 0.0
        return restored


def _own_copy(screen: Screen) -> Screen:
    """``screen`` with a private copy of its overlays (the window edits them in place)."""
    if screen.overlays is None:
        return screen
    return replace(screen, overlays=replace(screen.overlays))


def _keep_overlays(screen: Screen, current: Screen, same_step: bool) -> Screen:
    """``screen`` with the overlays on screen now when the step stays the same (the
    reader's additions survive a try-this), else as the step sets them."""
    if not same_step or current.overlays is None:
        return screen
    return replace(screen, overlays=replace(current.overlays))


# --- imgui ---------------------------------------------------------------------------------

def session_of(state: AppState) -> LessonSession:
    """The LessonSession kept on the app state (created and loaded on first use)."""
    if state.lesson_session is None:
        state.lesson_session = LessonSession.load(state.lesson_folder,
                                                  not state.lesson_folder_alone)
    return state.lesson_session


def current_screen(state: AppState) -> Screen:
    return Screen(settings=state.settings, compare_settings=state.compare_settings,
                  view_mode=state.view_mode, view_buffer=state.view_buffer,
                  compare_overrides=tuple(state.compare_overrides),
                  compare_variants=tuple(state.compare_variants),
                  overlays=replace(state.overlays), split_position=state.split_position)


def show_screen(state: AppState, screen: Screen) -> None:
    """Put ``screen`` into the app state (settings of A and B, view mode and buffer,
    in-scene overlays, inspect source, plot tab). Overlays bring the Show in scene panel
    forward (its controls), else an inspect source brings the Inspect panel."""
    state.settings = screen.settings
    state.compare_settings = screen.compare_settings
    state.view_mode = screen.view_mode
    state.compare_overrides = tuple(screen.compare_overrides)
    state.compare_variants = tuple(screen.compare_variants)
    state.view_buffer = screen.view_buffer
    if screen.split_position is not None:
        state.split_position = screen.split_position
    focus = []
    drawn = screen.overlays is not None and screen.overlays.any_shown
    if screen.overlays is not None:
        state.overlays = replace(screen.overlays)
    if screen.inspect_source is not None:
        state.inspect.source = screen.inspect_source
    if screen.inspect_source in NOT_IN_SCENE_VIEWS:
        focus.append("Inspect")
    elif drawn:
        focus.append("Show in scene")
        if screen.overlays.picked_kind != "none" and screen.plot is None:
            focus.append("Picked")
    elif screen.inspect_source is not None:
        focus.append("Inspect")
    from explorer.ui.panels.error import want_measurement

    want_measurement(state, screen.plot == "error")
    if screen.plot == "error":
        focus.append("Error")
    elif screen.plot is not None:
        state.plot_tab = screen.plot
        focus.append("Plots")
    if focus:
        state.requests.focus_panel = tuple(focus)
