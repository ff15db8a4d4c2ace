"""Step through every shipped lesson in the real window in the reader's mode and record what
it draws (a child process of tests/lessons/test_window_words.py; by hand:
``xvfb-run -a python tests/reader_walk.py [LESSON ...]``).

The imgui calls that put text on screen (text, labels of buttons, sliders, combos and
checkboxes, tooltips, the draw list's text) are wrapped for the walk, so the test reads
the strings from the drawing code paths themselves. Each step is applied, drawn until its
frame has a result, each panel the step uses is brought forward for a few frames, and one
frame is drawn with every item taken as hovered (every tooltip drawn). Besides the
strings, the walk records where a labelled widget or a line of text runs past the right
edge of its panel, a combo whose choice is clipped, a dock tab bar whose tabs are
shrunk, and the size of the Error panel's images; it then clicks the error image and
records what the enlarged view draws. The last line printed is a JSON report.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

# isort: off
from imgui_bundle import imgui  # noqa: E402  (before glfw: it points pyglfw at its GLFW)
# isort: on

WINDOW = (1280, 720)
FRAMES_PER_PANEL = 2
RESULT_WAIT_S = 60.0
SLACK_PX = 1.0
ENLARGED = "Error images##enlarged"
RENDER_SCALE = 0.25
"""The pipelines render at this share of the view's pixels (the walk reads words and
layout, not the picture)."""


class Recorder:
    """Wraps imgui's text-drawing calls while :attr:`on` and keeps what they drew."""

    def __init__(self) -> None:
        self.on = False
        self.where = ""
        self.texts: dict[str, set[str]] = {}
        self.overflows: dict[str, str] = {}
        self.images: list[dict] = []
        self.nodes: dict[int, object] = {}
        self.hover_all = False
        self._wrapped: list[tuple[object, str, object]] = []

    # -- recording ----------------------------------------------------------------------
    def text(self, text) -> None:
        if self.on and isinstance(text, str) and text.strip():
            shown = text.split("##")[0] if "##" in text else text
            if shown.strip():
                window = imgui.internal.get_current_window()
                name = window.name.split("##")[0] if window is not None else "?"
                self.texts.setdefault(shown, set()).add(f"{self.where} [{name}]")

    def _window(self) -> str:
        window = imgui.internal.get_current_window()
        return window.name if window is not None else "?"

    def _right_edge(self) -> float:
        return imgui.get_cursor_screen_pos().x + imgui.get_content_region_avail().x

    def _check_fits(self, label: str, right: float, what: str) -> None:
        """The last item ends within the panel's content region (else it is clipped)."""
        if not self.on:
            return
        end = imgui.get_item_rect_max().x
        window = imgui.internal.get_current_window()
        clip = window.inner_clip_rect.max.x if window is not None else right
        if end > min(right, clip) + SLACK_PX and imgui.is_item_visible():
            key = f"{self._window()}: {what} {label!r}"
            self.overflows.setdefault(key, f"{self.where}: ends at {end:.0f} px, the panel "
                                           f"at {min(right, clip):.0f} px")

    def _check_combo(self, label: str, preview: str) -> None:
        if not self.on or not preview:
            return
        style = imgui.get_style()
        shown = label.split("##")[0]
        width = imgui.get_item_rect_size().x
        if shown:
            width -= imgui.calc_text_size(shown).x + style.item_inner_spacing.x
        need = (imgui.calc_text_size(preview).x + 2 * style.frame_padding.x
                + imgui.get_frame_height())
        if need > width + SLACK_PX and imgui.is_item_visible():
            key = f"{self._window()}: combo {label!r} shows {preview!r}"
            self.overflows.setdefault(key, f"{self.where}: needs {need:.0f} px, has "
                                           f"{width:.0f}")

    def install(self) -> None:
        """Wrap the calls (for the rest of the process: the walk is a child of its own)."""
        for name in ("text", "text_disabled", "text_unformatted", "bullet_text",
                     "separator_text"):
            self._text_at(name, 0)
        self._text_at("text_colored", 1)
        self._text_at("text_wrapped", 0, check=False)
        self._text_at("set_tooltip", 0, check=False)
        for name in ("button", "small_button", "checkbox", "radio_button", "selectable",
                     "slider_float", "slider_int", "input_float", "input_int", "input_text",
                     "drag_float", "drag_int", "collapsing_header", "menu_item",
                     "menu_item_simple", "begin_menu", "begin_tab_item", "tree_node"):
            if hasattr(imgui, name):
                self._labelled(name)
        self._labelled("combo", combo=True)
        self._labelled("begin_combo", combo=True)
        self._others()

    def _labelled(self, name: str, combo: bool = False) -> None:
        rec, original = self, getattr(imgui, name)

        def call(*args, **kwargs):
            label = args[0] if args else kwargs.get("label", "")
            right = rec._right_edge() if rec.on else 0.0
            result = original(*args, **kwargs)
            if isinstance(label, str):
                rec.text(label)
                if label.split("##")[0]:
                    rec._check_fits(label.split("##")[0], right, name)
            if combo:
                preview = _combo_preview(name, args)
                rec.text(preview)
                rec._check_combo(label, preview)
            return result
        self._wrap(imgui, name, call, original)

    def _text_at(self, name: str, index: int, check: bool = True) -> None:
        rec, original = self, getattr(imgui, name)

        def call(*args, **kwargs):
            right = rec._right_edge() if rec.on else 0.0
            result = original(*args, **kwargs)
            text = args[index] if len(args) > index else ""
            rec.text(text)
            if check and isinstance(text, str) and "\n" not in text:
                rec._check_fits(text, right, name)
            return result
        self._wrap(imgui, name, call, original)

    def _others(self) -> None:
        """The draw list's text, the images, hovering (all at once in the hover frame)
        and the windows begun (their dock node's tab bar)."""
        rec = self
        original_add_text = imgui.ImDrawList.add_text

        def add_text(draw, *args, **kwargs):
            rec.text(next((a for a in args if isinstance(a, str)), kwargs.get("text_begin")))
            return original_add_text(draw, *args, **kwargs)
        self._wrap(imgui.ImDrawList, "add_text", add_text, original_add_text)
        original_image = imgui.image

        def image(texture, size, *args, **kwargs):
            result = original_image(texture, size, *args, **kwargs)
            if rec.on:
                lo, hi = imgui.get_item_rect_min(), imgui.get_item_rect_max()
                rec.images.append({"window": rec._window(), "where": rec.where,
                                   "rect": [lo.x, lo.y, hi.x, hi.y]})
            return result
        self._wrap(imgui, "image", image, original_image)
        original_hovered = imgui.is_item_hovered

        def is_item_hovered(*args, **kwargs):
            return True if rec.hover_all else original_hovered(*args, **kwargs)
        self._wrap(imgui, "is_item_hovered", is_item_hovered, original_hovered)
        original_begin = imgui.begin

        def begin(name, *args, **kwargs):
            result = original_begin(name, *args, **kwargs)
            rec.text(name)
            if rec.on:
                window = imgui.internal.get_current_window()
                node = window.dock_node if window is not None else None
                if node is not None and node.tab_bar is not None:
                    rec.nodes[node.id_] = node
            return result
        self._wrap(imgui, "begin", begin, original_begin)

    def _wrap(self, owner, name: str, call, original) -> None:
        self._wrapped.append((owner, name, original))
        setattr(owner, name, call)

    def check_tabs(self) -> None:
        """A dock tab bar whose tabs are narrower than their titles (imgui shrinks them)."""
        for node in self.nodes.values():
            bar = node.tab_bar
            if bar is None or not node.is_leaf_node():
                continue
            if bar.width_all_tabs + SLACK_PX < bar.width_all_tabs_ideal:
                names = [tab.window.name for tab in bar.tabs if tab.window is not None]
                self.overflows.setdefault(f"dock tabs {names}", f"{self.where}: "
                                          f"{bar.width_all_tabs:.0f} px of "
                                          f"{bar.width_all_tabs_ideal:.0f} needed")
        self.nodes.clear()


def _combo_preview(name: str, args) -> str:
    if name == "begin_combo":
        return args[1] if len(args) > 1 and isinstance(args[1], str) else ""
    if len(args) > 2 and isinstance(args[2], (list, tuple)) and 0 <= args[1] < len(args[2]):
        return str(args[2][args[1]])
    return ""


def _frames(app, rec: Recorder, count: int) -> None:
    for _ in range(count):
        app.frame(force=True)
        rec.check_tabs()


def _until_result(app, rec: Recorder) -> None:
    start = time.monotonic()
    rt = app.state.runtime
    while time.monotonic() - start < RESULT_WAIT_S:
        app.frame(force=True)
        rec.check_tabs()
        if rt.frame.result is not None and not app.drew_change:
            return


def walk(wanted: list[str]) -> dict:
    from click_sessions import small_error_measurement, small_settings

    from explorer.gl.window import headless_available
    from explorer.ui.app import App
    from explorer.ui.lesson_panel import (
        current_screen,
        session_of,
        show_screen,
        step_panels,
    )
    from explorer.ui.state import AppState
    from explorer.ui.window_options import WindowOptions

    rec = Recorder()
    rec.install()
    options = WindowOptions(width=WINDOW[0], height=WINDOW[1], visible=False, vsync=False,
                            persist_settings=False, headless=headless_available())
    # the reader's own settings small, as in the click sessions: the steps that set no
    # grid converge at 8³ (the strings and their places are the same; about a third of
    # the walk's CPU time at 32³ × 16, BENCHMARKS.md "The suite in minutes")
    app = App(AppState(settings=small_settings(), render_scale=RENDER_SCALE), options)
    state = app.state
    small_error_measurement(state)
    steps = 0
    enlarged: dict = {}
    try:
        _frames(app, rec, 3)
        session = session_of(state)
        lessons = [lesson for lesson in session.lessons
                   if not wanted or lesson.id in wanted or lesson.path.stem in wanted]
        for lesson in lessons:
            session.open(lesson.id)
            for step in lesson.steps:
                rec.where = f"{lesson.id} step {step.number}"
                session.go(step.number)
                show_screen(state, session.apply(current_screen(state)))
                _until_result(app, rec)
                rec.on = True
                for title in sorted(step_panels(step)):
                    state.requests.focus_panel = (title,)
                    _frames(app, rec, FRAMES_PER_PANEL)
                rec.hover_all = True
                _frames(app, rec, 1)
                rec.hover_all = False
                if "Error" in step_panels(step) and not enlarged:
                    enlarged = _enlarge(app, rec)
                rec.on = False
                steps += 1
            # the reader leaves the lesson's settings: the words of that state too
            rec.where = f"{lesson.id} after leaving"
            rec.on = True
            show_screen(state, session.leave())
            _frames(app, rec, 3)
            rec.hover_all = True
            _frames(app, rec, 1)
            rec.hover_all = False
            rec.on = False
    finally:
        app.close()
    return {"steps": steps, "texts": {text: sorted(where) for text, where in rec.texts.items()},
            "overflows": rec.overflows, "images": rec.images, "enlarged": enlarged}


def _enlarge(app, rec: Recorder) -> dict:
    """Wait for the Error panel's images, click the error image, and record the images
    the enlarged view draws."""
    start = time.monotonic()
    state = app.state
    state.requests.focus_panel = ("Error",)
    while time.monotonic() - start < RESULT_WAIT_S * 4:
        rec.images.clear()
        _frames(app, rec, 1)
        thumbs = [image for image in rec.images if image["window"] == "Error"]
        if len(thumbs) >= 3:
            break
    else:
        return {"problem": "the Error panel drew no images"}
    x0, y0, x1, y1 = thumbs[-1]["rect"]
    io = imgui.get_io()
    io.add_mouse_pos_event((x0 + x1) / 2, (y0 + y1) / 2)
    _frames(app, rec, 2)
    io.add_mouse_button_event(0, True)
    _frames(app, rec, 1)
    io.add_mouse_button_event(0, False)
    rec.images.clear()
    _frames(app, rec, 3)
    shown = [image["rect"] for image in rec.images if image["window"] == ENLARGED]
    result = {"thumbs": [t["rect"] for t in thumbs[-3:]], "clicked": [x0, y0, x1, y1],
              "enlarged": shown[-3:]}
    io.add_mouse_pos_event(5, 5)      # away again, then close the enlarged view
    io.add_key_event(imgui.Key.escape, True)
    _frames(app, rec, 1)
    io.add_key_event(imgui.Key.escape, False)
    rec.images.clear()
    _frames(app, rec, 2)
    result["closed"] = not any(image["window"] == ENLARGED for image in rec.images)
    return result


def main(argv: list[str]) -> int:
    report = walk(argv)
    print(json.dumps(report))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
