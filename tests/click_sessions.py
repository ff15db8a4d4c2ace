"""The click sessions tests/click_app.py runs: each a window state to start from and a
test function that drives the window through its controls by label
(explorer/ui/test_engine.py) and checks what each click shows.

Sessions group many clicks into one window (starting a window and its pipelines costs
seconds on llvmpipe); the reader's own settings are small (an 8³ grid, a 32² RSM, a
quarter-size render) so that only the lessons' own steps cost pipeline work.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Callable

LESSON = "//Lesson"
ARTICLE = "//Lesson/article"
LESSON_LIST = "//Lesson/contents"


@dataclass(frozen=True)
class Session:
    state: Callable
    run: Callable
    doc: str


def small_state():
    """The reader's own configuration at the start of every session."""
    from explorer.lpv.settings import Settings
    from explorer.ui.state import AppState

    return AppState(settings=Settings(grid_size=8, iterations=3, rsm_size=32),
                    render_scale=0.25)


def label_ref(label: str) -> str:
    """An item label as a test engine reference segment ("/" separates windows and ids
    in a reference: a label's own slashes are escaped)."""
    return label.replace("/", "\\/")


def _open_from_list(c, lesson) -> None:
    c.click_in(LESSON_LIST, label_ref(f"{lesson.number:02d}   {lesson.title}"),
               f"lesson list: {lesson.id}")


def _at_top(c, what: str) -> None:
    c.settle_input(2)
    scroll = c.scroll_y(ARTICLE)
    c.check(scroll == 0.0, f"{what}: the article opens at its top (scroll {scroll:.0f} px)")


def _shows(c, lesson, number: int, what: str) -> None:
    """The window shows ``lesson`` step ``number`` with the step's settings applied."""
    from explorer.ui.lesson_panel import shows_step

    session = c.state.lesson_session
    ok = session.lesson is not None and session.lesson.id == lesson.id
    c.check(ok and session.step_number == number,
            f"{what}: shows {lesson.id} step {number} (shows "
            f"{session.lesson.id if session.lesson else None} step {session.step_number})")
    if ok:
        step = lesson.step(number)
        c.check(session.applied and shows_step(c.state.settings, step),
                f"{what}: {lesson.id} step {number}'s settings are on screen")


def _to_step(c, lesson, number: int) -> None:
    """Pick step ``number`` from the step list (the combo above the article)."""
    step = lesson.step(number)
    c.click(f"{LESSON}/##steps", "step list")
    c.click(f"//$FOCUSED/{label_ref(f'{step.number}. {step.title}')}",
            f"step list: {lesson.id} {number}")


# --- lessons: every lesson, every step, Next / Previous / Next lesson / All lessons ------

def run_lessons(c) -> None:
    session = c.state.lesson_session
    own = c.state.settings
    lessons = session.lessons
    c.settle_input(3)
    # every lesson from the list, and back
    for lesson in lessons:
        _open_from_list(c, lesson)
        _shows(c, lesson, 1, f"open {lesson.id} from the list")
        _at_top(c, f"open {lesson.id}")
        c.click(f"{LESSON}/**/< All lessons", "< All lessons")
        c.check(session.lesson is None, f"< All lessons from {lesson.id}: the list shows")
        c.check(c.state.settings == own,
                f"< All lessons from {lesson.id}: the reader's own settings come back")
    # every step with Next, every Next lesson, from lesson 1 to the last
    _open_from_list(c, lessons[0])
    for index, lesson in enumerate(lessons):
        for number in range(2, len(lesson.steps) + 1):
            title = lesson.step(number).title
            c.click_in(ARTICLE, label_ref(f"Next: {title}  >"), "Next")
            _shows(c, lesson, number, f"Next to {lesson.id} {number}")
            _at_top(c, f"Next to {lesson.id} {number}")
        if index + 1 < len(lessons):
            following = lessons[index + 1]
            c.click_in(ARTICLE, label_ref(f"Next lesson: {following.title}  >"),
                       "Next lesson")
            _shows(c, following, 1, f"Next lesson to {following.id}")
            _at_top(c, f"Next lesson to {following.id}")
    # Previous, from the last step back to the first, opening each at its top
    last = lessons[-1]
    for number in range(len(last.steps) - 1, 0, -1):
        c.click(f"{LESSON}/##previous", "Previous")
        _shows(c, last, number, f"Previous to {last.id} {number}")
        _at_top(c, f"Previous to {last.id} {number}")
    c.click(f"{LESSON}/**/< All lessons", "< All lessons")


# --- where a lesson was left, the step list, leaving and coming back ----------------------

def run_return(c) -> None:
    session = c.state.lesson_session
    own = c.state.settings
    lesson = next(item for item in session.lessons if len(item.steps) >= 5)
    c.settle_input(3)
    _open_from_list(c, lesson)
    for number in [3, 5, 2, 4, 1]:                 # the step list, in any order
        c.wheel(ARTICLE, -2.0)                     # read a little way down first
        _to_step(c, lesson, number)
        _shows(c, lesson, number, f"step list to {lesson.id} {number}")
        _at_top(c, f"step list to {lesson.id} {number}")
    _to_step(c, lesson, 4)
    c.wheel(ARTICLE, -2.0)
    scrolled = c.scroll_y(ARTICLE)
    c.check(scrolled > 0, "the article scrolls")
    c.click(f"{LESSON}/**/< All lessons", "< All lessons")
    c.check(session.lesson is None and c.state.settings == own,
            "All lessons half-way: the list and the reader's settings")
    other = session.lessons[0]                     # another lesson meanwhile
    _open_from_list(c, other)
    _shows(c, other, 1, f"open {other.id} from the list")
    _at_top(c, f"open {other.id}")
    c.click(f"{LESSON}/**/< All lessons", "< All lessons")
    _open_from_list(c, lesson)
    _shows(c, lesson, 4, f"back to {lesson.id}: where it was left")
    c.settle_input(3)
    back = c.scroll_y(ARTICLE)
    c.check(abs(back - scrolled) < 2.0,
            f"back to {lesson.id}: scrolled as it was left ({back:.0f} px, was {scrolled:.0f})")
    # Leave lesson settings / Back to the lesson
    c.click(f"{LESSON}/**/Leave lesson settings", "Leave lesson settings")
    c.check(not session.applied and c.state.settings == own,
            "Leave lesson settings: the reader's own settings are on screen")
    c.click(f"{LESSON}/**/Back to the lesson", "Back to the lesson")
    _shows(c, lesson, 4, "Back to the lesson")
    # a change of the reader's, then Reset step
    c.menu("Presets/A: original")
    c.click(f"{LESSON}/**/Reset step", "Reset step")
    _shows(c, lesson, 4, "Reset step")
    c.click(f"{LESSON}/**/< All lessons", "< All lessons")


# --- every try-this and its Undo ---------------------------------------------------------

def run_try_this(c, lessons=None) -> None:
    from explorer.ui.article import try_label
    from explorer.ui.lesson_panel import try_screen

    session = c.state.lesson_session
    c.settle_input(3)
    for lesson in lessons or session.lessons:
        if not any(step.try_this for step in lesson.steps):
            continue
        _open_from_list(c, lesson)
        for step in lesson.steps:
            if not step.try_this:
                continue
            if session.step_number != step.number:
                _to_step(c, lesson, step.number)
            for index, item in enumerate(step.try_this, start=1):
                label, _ = try_label(item)
                where = f"{lesson.id} {step.number} try {index}"
                c.click_in(ARTICLE, label_ref(f"{label}##try{index}"), "try this")
                wanted = try_screen(step, index, session.saved)
                c.check(session.tried == index, f"{where}: the try-this is on screen")
                c.check(c.state.settings == wanted.settings
                        and c.state.view_mode == wanted.view_mode
                        and c.state.compare_settings.corrections
                        == wanted.compare_settings.corrections,
                        f"{where}: the settings the button sets")
                undo = label_ref(f"Undo: {label}##try{index}")
                c.check(c.find(ARTICLE, undo) is not None,
                        f"{where}: its button now reads Undo")
                if index % 2:
                    c.click_in(ARTICLE, undo, "try this: Undo (its button)")
                else:
                    c.click(f"{LESSON}/**/Undo", "try this: Undo (the status line)")
                _shows(c, lesson, step.number, f"{where} undone")
                c.check(session.tried is None, f"{where} undone: no try-this on screen")
        c.click(f"{LESSON}/**/< All lessons", "< All lessons")


def _panel_titles() -> list[str]:
    from explorer.ui.layout import PANELS

    return [panel.title for panel in PANELS]


# --- the tool panels: menus, view modes, corrections, presets, layout --------------------

def run_window(c) -> None:
    from explorer.lpv.corrections import CORRECTIONS
    from explorer.lpv.settings import PRESETS

    state = c.state
    c.settle_input(3)
    # View: Single / Split / Difference, each changing what the view shows
    c.click("//Corrections/**/Original (as published)", "Corrections: Original preset")
    c.check(state.settings.corrections == PRESETS["original"], "Original preset applied")
    c.click("//Corrections/**/Corrected", "Corrections: Corrected preset")
    c.check(state.settings.corrections == PRESETS["corrected"], "Corrected preset applied")
    for mode in ("Split", "Difference", "Single"):
        c.picture_changes(lambda m=mode: c.click(f"//View/**/{m}", f"View: {m}"),
                          f"View: {mode}")
        c.check(state.view_mode == mode.lower(), f"View: {mode} is the view mode")
    # every correction switch, off and on again
    for entry in CORRECTIONS:
        ref = f"//Corrections/**/{label_ref(entry.title)}"
        was = getattr(state.settings.corrections, entry.name)
        c.click(ref, f"Corrections: {entry.title}")
        c.check(getattr(state.settings.corrections, entry.name) is (not was),
                f"Corrections: {entry.title} switches {'off' if was else 'on'}")
        c.click(ref, f"Corrections: {entry.title}")
        c.check(getattr(state.settings.corrections, entry.name) is was,
                f"Corrections: {entry.title} switches back")
    first = CORRECTIONS[0]
    c.picture_changes(lambda: c.click(f"//Corrections/**/{label_ref(first.title)}",
                                      f"Corrections: {first.title}"),
                      f"Corrections: {first.title}")
    c.click(f"//Corrections/**/{label_ref(first.title)}", f"Corrections: {first.title}")
    # the menus: presets for A and B, every window hidden and shown, reset layout
    for name in PRESETS:
        c.menu(f"Presets/A: {name}")
        c.check(state.settings.corrections == PRESETS[name], f"Presets/A: {name}")
        c.menu(f"Presets/B: {name}")
        c.check(state.compare_settings.corrections == PRESETS[name], f"Presets/B: {name}")
    for title in _panel_titles():
        c.menu(f"Windows/{label_ref(title)}")
        c.check(state.open_panels.get(title) is False,
                f"Windows/{title} hides it ({state.open_panels.get(title)})")
        window = c.window(f"//{label_ref(title)}")
        c.check(window is None or not window.active, f"Windows/{title}: the window is gone")
        c.menu(f"Windows/{label_ref(title)}")
        c.check(state.open_panels.get(title) is True,
                f"Windows/{title} shows it again ({state.open_panels.get(title)})")
    c.menu("Windows/Reset layout")
    c.settle_input(3)
    c.check(all(state.open_panels.get(title, True) for title in _panel_titles()),
            "Windows/Reset layout: every window shown")
    lesson = c.window("//Lesson")
    c.check(lesson is not None and lesson.dock_node is not None,
            "Windows/Reset layout: the Lesson column is docked")
    # File: Screenshot writes the window; Open mesh… is there (greyed without a dialog)
    c.menu("File/Screenshot")
    c.check(any("screenshot written to" in m.text for m in state.messages),
            "File/Screenshot: says where it wrote the picture")
    shots = list(Path.cwd().glob("lpv-explorer-*.png"))
    c.check(bool(shots), "File/Screenshot: the PNG is there")
    c.expect_quit = True
    c.menu("File/Quit")
    c.check(c.quit_seen, "File/Quit closes the window")


def run_explore(c) -> None:
    c.settle_input(3)
    print("conv", c.converged(), c.state.runtime.view_rect, flush=True)
    px = c.view_pixels()
    print("px", None if px is None else px.shape, c.app.last_pixels is None, flush=True)
    for t in ("View", "Lesson"):
        c.menu(f"Windows/{t}")
        print(t, c.state.open_panels.get(t), flush=True)
        c.menu(f"Windows/{t}")
        print(t, c.state.open_panels.get(t), flush=True)


SESSIONS = {
    "explore": Session(small_state, run_explore, ""),
    "lessons": Session(small_state, run_lessons,
                       "every lesson from the list and back, every step with Next, every "
                       "Next lesson, Previous back to the first step"),
    "return": Session(small_state, run_return,
                      "the step list, a lesson left half-way comes back there, Leave "
                      "lesson settings / Back to the lesson, Reset step"),
    "try-this": Session(small_state, run_try_this, "every try-this and its Undo"),
    "window": Session(small_state, run_window,
                      "Split/Difference/Single, every Corrections checkbox and preset, "
                      "every menu item (Presets, Windows, Reset layout, File)"),
}
