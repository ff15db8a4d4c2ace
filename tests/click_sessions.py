"""The click sessions tests/click_app.py runs: each a window state to start from and a
test function that drives the window through its controls by label
(explorer/ui/test_engine.py) and checks what each click shows.

Sessions group many clicks into one window (starting a window and its pipelines costs
seconds on llvmpipe); the reader's own settings are small (an 8³ grid, a 32² RSM, a
quarter-size render) so that only the lessons' own steps cost pipeline work.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

LESSON = "//Lesson"
ARTICLE = "//Lesson/article"
LESSON_LIST = "//Lesson/contents"


@dataclass(frozen=True)
class Session:
    state: Callable
    run: Callable
    doc: str


CLICK_BUDGET_MS = 2.0
"""Pipeline work per frame while the session clicks (a reader's input keeps the window to
the frame budget): the least the setting allows, so frames stay short (no check but the
window session's waits needs a converged frame; those get the quiet budget meanwhile) and
more of them see the frame converging (the provisional numbers of a try-this)."""


def small_settings():
    """The reader's own settings at the start of every session and of the reader walk
    (tests/reader_walk.py): a step that sets no grid, iterations or RSM runs at these."""
    from explorer.lpv.settings import Settings

    return Settings(grid_size=8, iterations=3, rsm_size=32)


def small_state():
    """The reader's own configuration at the start of every session."""
    from explorer.ui.state import AppState

    return AppState(settings=small_settings(), render_scale=0.25,
                    frame_budget_ms=CLICK_BUDGET_MS)


ERROR_RSM_SIZE = 16
"""The Error panel's measurement in the sessions and the reader walk: its RSM at the
panel's smallest choice (the reference costs pixels × VPLs: 256 VPLs instead of 4 096),
its pixels as shipped (the images, their layout and the size combo's text as a reader
sees them)."""


def small_error_measurement(state) -> None:
    """Measure the Error panel's configurations at :data:`ERROR_RSM_SIZE`, as a reader who
    picked that RSM in its combo."""
    from dataclasses import replace

    from explorer.ui.panels.error import error_service

    service = error_service(state)
    service.measurement = replace(service.measurement, rsm_size=ERROR_RSM_SIZE)


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
        c.check(_same_settings(c.state.settings, own),
                f"< All lessons from {lesson.id}: the reader's own settings come back "
                f"({_settings_difference(c.state.settings, own)})")
    # every step with Next, every Next lesson, from lesson 1 to the last
    _open_from_list(c, lessons[0])
    for index, lesson in enumerate(lessons):
        for number in range(2, len(lesson.steps) + 1):
            title = lesson.step(number).title
            c.click_until(ARTICLE, label_ref(f"Next: {title}  >"),
                          lambda n=number: session.step_number == n, "Next")
            _shows(c, lesson, number, f"Next to {lesson.id} {number}")
            _at_top(c, f"Next to {lesson.id} {number}")
        if index + 1 < len(lessons):
            following = lessons[index + 1]
            c.click_until(ARTICLE, label_ref(f"Next lesson: {following.title}  >"),
                          lambda f=following: session.lesson is not None
                          and session.lesson.id == f.id, "Next lesson")
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
    c.check(session.lesson is None and _same_settings(c.state.settings, own),
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
    c.check(not session.applied and _same_settings(c.state.settings, own),
            "Leave lesson settings: the reader's own settings are on screen")
    c.click(f"{LESSON}/**/Back to the lesson", "Back to the lesson")
    _shows(c, lesson, 4, "Back to the lesson")
    # a change of the reader's, then Reset step
    c.menu("Presets/A: original")
    c.click(f"{LESSON}/**/Reset step", "Reset step")
    _shows(c, lesson, 4, "Reset step")
    c.click(f"{LESSON}/**/< All lessons", "< All lessons")


_VIEW_SIZED = ("width", "height")
"""Settings the window sets itself (the render size follows the View panel)."""


def _same_settings(shown, wanted) -> bool:
    return shown == wanted.with_changes(**{name: getattr(shown, name) for name in _VIEW_SIZED})


def _settings_difference(shown, wanted) -> str:
    from dataclasses import fields

    differ = [f"{f.name}: {getattr(shown, f.name)!r} != {getattr(wanted, f.name)!r}"
              for f in fields(shown) if f.name not in _VIEW_SIZED
              and getattr(shown, f.name) != getattr(wanted, f.name)]
    return "; ".join(differ) or "the same settings"


def _provisional_while_converging(c, step, where: str) -> None:
    """While the frame converges (the view says "propagating k/N"), every number the
    step's text reads from the frame is drawn marked provisional (≈)."""
    from explorer.lessons import live_values
    from explorer.lessons import text as lesson_text
    from explorer.ui import article, article_numbers

    progress = c.state.runtime.frame.progress.get("A")
    if not progress:
        return
    session = c.state.lesson_session
    env = article._page_env(c.state, session, step, article_numbers.live_context(c.state, step))
    for name, fmt in lesson_text.placeholders(step.text):
        if not article_numbers.provisional(live_values.lookup(name, step.figure_ids,
                                                              step.mark_ids)):
            continue
        text, tip = env.value(name, fmt)
        if text != live_values.PENDING and c.state.runtime.frame.progress.get("A"):
            c.check(text.startswith(article_numbers.PROVISIONAL) and "provisional" in tip,
                    f"{where}: {name} reads {text!r} while the frame is {progress}")


# --- every try-this and its Undo ---------------------------------------------------------

def run_try_this(c, lessons=None) -> None:
    from explorer.ui.article_try import try_label
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
                c.click_until(ARTICLE, label_ref(f"{label}##try{index}"),
                              lambda i=index: session.tried == i, "try this")
                wanted = try_screen(step, index, session.saved)
                c.check(session.tried == index, f"{where}: the try-this is on screen")
                shown = c.state.settings
                c.check(_same_settings(shown, wanted.settings)
                        and c.state.view_mode == wanted.view_mode
                        and c.state.compare_settings.corrections
                        == wanted.compare_settings.corrections
                        and tuple(c.state.compare_overrides)
                        == tuple(wanted.compare_overrides),
                        f"{where}: the settings the button sets "
                        f"({_settings_difference(shown, wanted.settings)}, view "
                        f"{c.state.view_mode} / {wanted.view_mode})")
                _provisional_while_converging(c, step, where)
                undo = label_ref(f"Undo: {label}##try{index}")
                c.check(c.find(ARTICLE, undo) is not None,
                        f"{where}: its button now reads Undo")
                if index % 2:
                    c.click_until(ARTICLE, undo, lambda: session.tried is None,
                                  "try this: Undo (its button)")
                else:
                    c.click_until(LESSON, "Undo", lambda: session.tried is None,
                                  "try this: Undo (the status line)")
                _shows(c, lesson, step.number, f"{where} undone")
                c.check(session.tried is None, f"{where} undone: no try-this on screen")
        c.click(f"{LESSON}/**/< All lessons", "< All lessons")


# --- every inline figure's controls -------------------------------------------------------

def _figure_state(c, spec):
    from explorer.ui.article_numbers import figure_context
    from explorer.ui.figures import FIGURES

    return figure_context(c.state).state_for(spec.instance_id, spec.kind, spec.params,
                                             FIGURES[spec.kind].make_state)


def _drag(c, start, delta, what: str) -> None:
    """Press the mouse at ``start`` (screen pixels), move it by ``delta`` over a few
    frames, release."""
    from imgui_bundle import imgui

    # implot takes a handle that was hovered for a few frames before the press
    c.ctx.mouse_move_to_pos(imgui.ImVec2(float(start[0]), float(start[1])))
    c.settle_input(5)
    c.ctx.mouse_down(0)
    c.settle_input(5)
    for part in (0.2, 0.4, 0.6, 0.8, 1.0):
        c.ctx.mouse_move_to_pos(imgui.ImVec2(float(start[0] + part * delta[0]),
                                             float(start[1] + part * delta[1])))
        c.settle_input()
    c.ctx.mouse_up(0)
    c.controls.append(what)
    c.settle_input()


def _below(c, known: str, dx: float):
    """Click the widget on the line below the item labelled ``known``, ``dx`` pixels in
    from its left edge (for a widget whose label the engine's search does not see: the
    stepper's glyph combo under its Play button)."""
    from imgui_bundle import imgui

    ref = c.find(ARTICLE, known)
    if ref is None:
        return False
    rect = c.ctx.item_info(ref, imgui.test_engine.TestOpFlags_.no_error).rect_full
    spacing = imgui.get_style().item_spacing.y
    c.ctx.mouse_move_to_pos(imgui.ImVec2(rect.min.x + dx,
                                         rect.max.y + spacing + imgui.get_frame_height() / 2))
    c.ctx.mouse_click(0)
    c.settle_input()
    return True


WHEEL_PX = 5 * 15.0
"""What one wheel notch scrolls a window by (imgui: five lines of its font)."""


def _reveal(c, where):
    """Scroll the article until the screen point ``where()`` (a figure's handle, drawn
    each frame) lies in its middle third; the point then, or None."""
    for _ in range(6):                 # the point moves with the scroll: look again
        window = c.window(ARTICLE)
        point = where()
        if window is None or point is None:
            return point
        middle = window.pos.y + 0.5 * window.size.y
        if abs(point.y - middle) <= window.size.y / 6:
            break
        # the wheel, not a set offset: the figure's text may change height meanwhile
        notches = max(min((middle - point.y) / WHEEL_PX, 8.0), -8.0)
        c.wheel(ARTICLE, notches, record=False)
        c.settle_input(2)
    return where()


def _scale_controls(c, spec, figure, where: str) -> None:
    for scale in ("log", "linear", "auto"):
        c.click_in(ARTICLE, scale, f"{spec.kind}: axis {scale}")
        c.check(figure().scale == scale, f"{where}: the axis is {scale}")


# complexity: one branch per kind of control a figure draws
def _figure_controls(c, spec, where: str) -> None:  # noqa: C901
    """Every control of the figure ``spec`` on screen, each checked on the figure's state."""
    from explorer.figure_params import PIPELINE_STAGES, STEPPER_GLYPHS
    from explorer.ui.figures.cell_faces import neighbour_faces

    def figure():
        return _figure_state(c, spec)

    c.settle_input(2)
    if spec.kind == "pipeline":
        for key, title, _ in PIPELINE_STAGES:
            c.click_in(ARTICLE, f"##stage-{key}", f"pipeline: {title}")
            c.check(figure().highlight == key, f"{where}: {title} is lit")
    elif spec.kind in ("flux-per-step", "energy-audit"):
        _scale_controls(c, spec, figure, where)
        was = figure().relative
        c.click_in(ARTICLE, "share of injected", f"{spec.kind}: share")
        c.check(figure().relative is (not was), f"{where}: share of injected")
    elif spec.kind == "cell-faces":
        for index, face in enumerate(neighbour_faces(spec.params.direction)):
            c.click_in(ARTICLE, label_ref(f"{face.name}##row{index}"),
                       f"cell-faces: row {face.name}")
            c.check(figure().highlighted == index, f"{where}: face {face.name} highlighted")
    elif spec.kind == "propagation-stepper":
        c.click_in(ARTICLE, "Play", "stepper: Play")
        c.check(figure().playing, f"{where}: plays")
        c.click_in(ARTICLE, "Pause", "stepper: Pause")
        c.check(not figure().playing, f"{where}: pauses")
        ref = c.find(ARTICLE, "##t")
        if c.check(ref is not None, f"{where}: the step slider"):
            c.ctx.item_input_value(ref, 2)
            c.controls.append("stepper: step slider")
            c.settle_input()
            c.check(figure().step == 2, f"{where}: the slider sets step 2")
        for index, glyph in enumerate(STEPPER_GLYPHS):
            # the engine's search misses the combo's label: it is under Play
            if c.check(_below(c, "Play", 40.0), f"{where}: the glyph list"):
                c.controls.append("stepper: glyph list")
                # imgui.combo's entries: selectables under push_id(index)
                c.click(f"//$FOCUSED/$${index}/{label_ref(glyph)}", f"stepper: glyph {glyph}")
                c.check(figure().glyph == glyph, f"{where}: glyph {glyph}")
        _scale_controls(c, spec, figure, where)
    elif spec.kind in ("clamped-cosine", "rsm-texel"):
        handles = ((("n", "normal_deg", (25.0, 12.0)), ("ω", "probe_deg", (25.0, 12.0)))
                   if spec.kind == "clamped-cosine" else (("tilt", "theta_deg", (24., -20.)),))
        for handle, attribute, delta in handles:
            c.settle_input(2)
            before = after = getattr(figure(), attribute)
            for _ in range(2):           # implot takes a handle hovered long enough
                at = _reveal(c, lambda h=handle: figure().handles.get(h))
                if not c.check(at is not None, f"{where}: the {handle} handle is drawn"):
                    break
                _drag(c, (at.x, at.y), delta, f"{spec.kind}: drag {handle}")
                after = getattr(figure(), attribute)
                if abs(after - before) > 1.0:
                    break
            c.check(abs(after - before) > 1.0,
                    f"{where}: dragging {handle} moves it ({before:.1f} -> {after:.1f})")
    elif spec.kind == "small-multiples":
        pass                     # no controls: its panels answer hovering with tooltips
    else:
        c.check(False, f"{where}: no clicks written for figure kind {spec.kind}")


def run_figures(c, only=None) -> None:
    session = c.state.lesson_session
    c.settle_input(3)
    for lesson in session.lessons:
        steps = [step for step in lesson.steps if step.figures
                 and (only is None or (lesson.id, step.number) in only)]
        if not steps:
            continue
        _open_from_list(c, lesson)
        for step in steps:
            if session.step_number != step.number:
                _to_step(c, lesson, step.number)
            for spec in step.figures:
                _figure_controls(c, spec, f"{lesson.id} {step.number} {spec.kind}")
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
        title = label_ref(entry.title)
        was = getattr(state.settings.corrections, entry.name)
        c.click_in("//Corrections", title, f"Corrections: {entry.title}")
        c.check(getattr(state.settings.corrections, entry.name) is (not was),
                f"Corrections: {entry.title} switches {'off' if was else 'on'}")
        c.click_in("//Corrections", title, f"Corrections: {entry.title}")
        c.check(getattr(state.settings.corrections, entry.name) is was,
                f"Corrections: {entry.title} switches back")
    # the Compare panel: its view modes, B's presets, Swap A/B, every B switch
    c.ctx.window_focus("//Compare")
    c.settle_input(2)
    for mode in ("Split", "Difference", "Single"):
        c.click(f"//Compare/**/{mode}##cmp", f"Compare: {mode}")
        c.check(state.view_mode == mode.lower(), f"Compare: {mode} is the view mode")
    for name in PRESETS:
        c.click(f"//Compare/**/{name.capitalize()}##B", f"Compare: B {name}")
        c.check(state.compare_settings.corrections == PRESETS[name], f"Compare: B {name}")
    a, b = state.settings.corrections, state.compare_settings.corrections
    c.click("//Compare/**/Swap A\\/B", "Compare: Swap A/B")
    c.check(state.settings.corrections == b and state.compare_settings.corrections == a,
            "Compare: Swap A/B swaps the corrections")
    c.click("//Compare/**/Swap A\\/B", "Compare: Swap A/B")
    for entry in CORRECTIONS:
        was = getattr(state.compare_settings.corrections, entry.name)
        label = f"{label_ref(entry.title)}##B"
        c.click_in("//Compare", label, f"Compare: B {entry.title}")
        c.check(getattr(state.compare_settings.corrections, entry.name) is (not was),
                f"Compare: B {entry.title} switches")
        c.click_in("//Compare", label, f"Compare: B {entry.title}")
    c.ctx.window_focus("//Corrections")            # its tab forward again
    first = CORRECTIONS[0]
    c.picture_changes(lambda: c.click_in("//Corrections", label_ref(first.title),
                                         f"Corrections: {first.title}"),
                      f"Corrections: {first.title}")
    c.click_in("//Corrections", label_ref(first.title), f"Corrections: {first.title}")
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


SESSIONS = {
    "lessons": Session(small_state, run_lessons,
                       "every lesson from the list and back, every step with Next, every "
                       "Next lesson, Previous back to the first step"),
    "return": Session(small_state, run_return,
                      "the step list, a lesson left half-way comes back there, Leave "
                      "lesson settings / Back to the lesson, Reset step"),
    "try-this": Session(small_state, run_try_this, "every try-this and its Undo"),
    "figures": Session(small_state, run_figures, "every inline figure's controls"),
    "figures-drag": Session(small_state, lambda c: run_figures(c, {
        ("spherical-harmonics", 2), ("reflective-shadow-maps", 2), ("solid-angles", 5)}),
        "the draggable figures and the stepper (a short session for trying fixes)"),
    "window": Session(small_state, run_window,
                      "Split/Difference/Single, every Corrections checkbox and preset, "
                      "every menu item (Presets, Windows, Reset layout, File)"),
}
