"""Run click sessions in the real explorer window (a child process of the click tests,
tests/ui/test_click_window.py; or by hand: ``python tests/click_app.py navigation``).

Each session is one window and one Dear ImGui Test Engine test (explorer/ui/
test_engine.py) whose function clicks, drags and types through the window by label and
checks what each action shows. A session fails on a failed check, on a Python exception
in the test or in any panel (the window's panels report theirs and keep running), and on
an imgui assert (the process aborts). The last line printed is a JSON report:
``{"session": ..., "passed": ..., "clicks": N, "controls": [...], "problems": [...],
"seconds": ...}``.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from click_labels import DrawnLabels  # noqa: E402  (tests/ on the path first)

WINDOW = (1280, 720)
SESSION_TIMEOUT_S = 900.0
ON_TOP = ("//Lesson/", "//$FOCUSED/")
"""Windows always in front when a session clicks in them (the Lesson column, an open
popup): an item drawn whole there is clicked where it is (:meth:`Clicks._press`), with
no engine step to bring its window forward."""
PAGE_FRACTION = 0.7
"""A search scrolls this much of the window's height a step (the rest overlaps)."""


class Clicks:
    """What a session's test function uses: the engine's test context, the app, and
    checks that collect failures instead of stopping at the first."""

    def __init__(self, app, ctx, problems: list[str], shots: Path | None) -> None:
        self.app = app
        self.state = app.state
        self.ctx = ctx
        self.problems = problems
        self.controls: list[str] = []
        self.shots = shots
        self._seen_errors = 0
        self.waiting = False
        """The session waits for the pipelines (:meth:`until`): the runner stops telling
        the window that input arrives, so it works with the quiet budget."""
        self.expect_quit = False
        """The next action asks the window to close (File/Quit): the runner notes it
        (:attr:`quit_seen`) and keeps the window open for the rest of the session."""
        self.quit_seen = False
        self._found: tuple[str, int] = ("", 0)
        """The reference :meth:`_item_id` looked up last and the ID it found (0: none)."""
        self.labels: DrawnLabels | None = None
        """What the window drew (:mod:`click_labels`): :meth:`find` asks the engine for a
        label only where it was drawn."""

    # -- actions ----------------------------------------------------------------------
    def click(self, ref: str, what: str | None = None) -> None:
        """Click the item ``ref`` (a test engine reference: "//Window/**/label"), then
        let a frame run; a panel failing on it is a problem named after the click. An
        item the engine cannot find is a failed check (the engine itself would stop the
        whole session at it)."""
        from imgui_bundle import imgui

        target, at = ref, None
        if "**" in ref or ref.startswith(ON_TOP):
            info = self.ctx.item_info(ref, imgui.test_engine.TestOpFlags_.no_error)
            found = info.id_ if info is not None else 0
            if not found and "**" in ref:
                self.check(False, f"{what or ref}: no item {ref!r} on screen")
                return
            if found:
                target = found
                at = _inside(info) if ref.startswith(ON_TOP) else None
        self._press(target, what or ref, at)

    def _press(self, target, what: str, at=None) -> None:
        """Click ``target`` (a reference, or the ID :meth:`_item_id` found: the engine
        then looks for no label again, a frame sooner), let the frames after it run and
        collect what the panels reported. ``at``: the screen point of an item standing
        still on screen (:meth:`_steady`): the mouse goes there and clicks, 4 frames
        where the engine's item click takes 9 (it looks the item up, brings its window
        forward, scrolls it into view and checks the hover first)."""
        from imgui_bundle import imgui

        te = imgui.test_engine
        if at is not None:
            self.ctx.mouse_move_to_pos(at)
            self.ctx.mouse_down(0)
            self.ctx.mouse_up(0)
        else:
            if isinstance(target, int):
                target = te.TestRef(target)
            # no engine error either when it goes between finding and clicking (the text
            # reflowed): the session's own checks see what the click did or did not do
            self.ctx.item_click(target, 0, te.TestOpFlags_.no_error
                                | te.TestOpFlags_.no_check_hovered_id)
        self.controls.append(what)
        self.settle_input()
        self._panel_errors(what)

    def click_in(self, window_ref: str, label: str, what: str | None = None) -> bool:
        """Click the item labelled ``label`` (escaped, :func:`label_ref`) in the window
        or child window ``window_ref``, scrolling it into view first as a reader would
        (the engine finds an item by its label only once it was drawn on screen)."""
        ref = self.find(window_ref, label)
        if ref is None:
            self.check(False, f"no item {label!r} in {window_ref}")
            return False
        item, at = self._steady(ref)
        self._press(item or ref, what or ref, at)
        return True

    def click_until(self, window_ref: str, label: str, done, what: str,
                    attempts: int = 3) -> bool:
        """Click the item ``label`` in ``window_ref`` until ``done()`` holds: a lesson's
        text reflows while its frame converges (a number arrives, a note goes), so an
        item can move between the engine finding it and the mouse arriving; the click
        waits for the item to stand still and is tried again if it missed."""
        for _ in range(attempts):
            ref = self.find(window_ref, label)
            if ref is None:
                self.check(False, f"no item {label!r} in {window_ref}")
                return False
            # no engine error for an item gone meanwhile (_press): it would stop the
            # whole session
            item, at = self._steady(ref)
            self._press(item or ref, what, at)
            if done():
                return True
        return self.check(False, f"{what}: {attempts} clicks on {label!r} did nothing")

    def _steady(self, ref: str, frames: int = 40) -> tuple[int, object]:
        """Wait until the item ``ref`` stays where it is for two frames; its ID (0 when
        it went meanwhile) and, when it is wholly visible, the centre of its rectangle
        (None otherwise: the engine's click then scrolls it into view)."""
        from imgui_bundle import imgui

        te = imgui.test_engine
        last, target, item = None, ref, 0
        if self._found[0] == ref and self._found[1]:
            # the ID :meth:`find` just saw: by it the engine answers from the frame just
            # drawn, where a label is searched for again over a frame or two
            target = te.TestRef(self._found[1])
        for _ in range(frames):
            info = self.ctx.item_info(target, te.TestOpFlags_.no_error)
            rect = None if info is None else (info.rect_full.min.x, info.rect_full.min.y)
            item = 0 if info is None else info.id_
            if rect is not None and rect == last:
                return item, _inside(info)
            last = rect
            if item:
                target = te.TestRef(item)
            self.ctx.yield_()
        return item, None

    def _item_id(self, ref: str) -> int:
        """The ID of the item ``ref`` names, 0 if none is on screen (no engine error)."""
        from imgui_bundle import imgui

        info = self.ctx.item_info(ref, imgui.test_engine.TestOpFlags_.no_error)
        self._found = (ref, info.id_ if info is not None else 0)
        return self._found[1]

    def find(self, window_ref: str, label: str) -> str | None:
        """The reference of the item labelled ``label`` in ``window_ref``, scrolled on
        screen; None if the window has none."""
        from imgui_bundle import imgui

        # a wildcard search runs from the top-level window (the engine does not take a
        # child window as its start); the child is what scrolls
        name = window_ref.removeprefix("//").split("/")[0]
        ref = f"//{name}/**/{label}"
        if self._found[0] == ref and self._found[1] and self.ctx.item_info(
                imgui.test_engine.TestRef(self._found[1]),
                imgui.test_engine.TestOpFlags_.no_error).id_:
            return ref                 # the item just found is still there, by its ID
        # in a child window (the article, the lesson list) a miss costs the engine six
        # frames a page; in a top-level one the engine's own miss pans that window, and
        # finds an item scrolled away in a frame or two: it is asked at once
        hinted = self.labels is not None and "/" in window_ref.removeprefix("//")
        if (not hinted or self._drawn(name, label)) and self.exists(ref):
            return ref
        found = self._search(window_ref, ref, name, label, hinted=hinted)
        if found is None and hinted:
            # by the engine on every page: an item of a kind DrawnLabels does not see
            found = self._search(window_ref, ref, name, label, hinted=False)
        return found

    def _drawn(self, name: str, label: str) -> bool:
        """Whether the last frame drew ``label`` visible in the window ``name`` (True
        when nobody records what is drawn: the engine is asked every time)."""
        return self.labels is None or self.labels.seen(name.replace("\\/", "/"), label)

    def _search(self, window_ref: str, ref: str, name: str, label: str,
                hinted: bool) -> str | None:
        """:meth:`find`'s scroll from the top, a page at a time; ``hinted``: ask the engine
        only on a page where :attr:`labels` saw the label drawn."""
        from imgui_bundle import imgui

        te = imgui.test_engine
        window = self._window_soon(window_ref)
        if window is None:
            return None
        self.ctx.scroll_to_top(te.TestRef(window.id_))
        # down with the wheel, as a reader does: the text may grow or shrink meanwhile
        # (a number arrives, a banner goes), where a scroll to a set offset would fail
        # (until the wheel moves it no more: a text just opened knows its height only
        # once it was drawn, so its scroll limit is not trusted). A page at a time: an
        # item drawn partly inside the window is found, so a step shorter than the
        # window by more than a button's height passes over none (the search itself
        # draws the frames the scroll needs, no settling in between)
        last, still = None, 0
        for _ in range(200):
            if (not hinted or self._drawn(name, label)) and self.exists(ref):
                return ref
            window = self._window_soon(window_ref)
            if window is None:
                return None
            still = still + 1 if window.scroll.y == last else 0
            if still >= 2:
                return None
            last = window.scroll.y
            self.wheel(window_ref, -self._page_notches(window), record=False, settle=False)
            if hinted:
                self.ctx.yield_()      # the page drawn at its new scroll
        return None

    @staticmethod
    def _page_notches(window) -> float:
        """Wheel notches that scroll ``window`` by at most :data:`PAGE_FRACTION` of its
        height (at least the two notches of a reader's flick)."""
        from click_sessions import WHEEL_PX

        return float(max(2, int(PAGE_FRACTION * window.size.y / WHEEL_PX)))

    def check_box(self, ref: str, on: bool, what: str | None = None) -> None:
        (self.ctx.item_check if on else self.ctx.item_uncheck)(ref)
        self.controls.append(what or ref)
        self.settle_input()
        self._panel_errors(what or ref)

    def menu(self, path: str) -> None:
        """A main-menu item, e.g. "Windows/Reset layout"."""
        self.ctx.menu_click("//##MainMenuBar/" + path)
        self.controls.append("menu " + path)
        self.settle_input()
        self._panel_errors("menu " + path)

    def wheel(self, window_ref: str, notches: float, record: bool = True,
              settle: bool = True) -> None:
        """Turn the mouse wheel over a window's right edge (its scroll bar: over a plot
        in the text the wheel would zoom the plot instead), half-way down; negative
        notches scroll down. ``settle``: let the frames after it run (a caller that
        looks for an item next draws them while it looks)."""
        from imgui_bundle import imgui

        window = self.window(window_ref)
        if window is None:
            self.problems.append(f"no window {window_ref} to scroll")
            return
        target = imgui.ImVec2(window.pos.x + window.size.x - 5.0,
                              window.pos.y + window.size.y * 0.5)
        mouse = imgui.get_io().mouse_pos
        # the engine's move takes two frames even to where the mouse already is (a
        # search scrolling down page after page turns the wheel there again and again)
        if abs(mouse.x - target.x) > 0.5 or abs(mouse.y - target.y) > 0.5:
            self.ctx.mouse_move_to_pos(target)
        self.ctx.mouse_wheel_y(notches)
        if record:
            self.controls.append(f"wheel over {window_ref}")
        if settle:
            self.settle_input()

    def settle_input(self, frames: int = 2) -> None:
        self.ctx.yield_(frames)

    def until(self, predicate, what: str, frames: int = 600) -> bool:
        """Draw frames until ``predicate()``; a problem when it never holds."""
        self.waiting = True
        try:
            for _ in range(frames):
                if predicate():
                    return True
                self.ctx.yield_()
        finally:
            self.waiting = False
        self.problems.append(f"never happened within {frames} frames: {what}")
        return False

    def converged(self, frames: int = 3000) -> bool:
        """Draw frames until the pipelines have nothing left to do."""
        app = self.app
        return self.until(lambda: app.status is not None and not app.status.active
                          and app.state.runtime.frame.result is not None,
                          "the frame converged", frames)

    # -- checks -----------------------------------------------------------------------
    def check(self, condition: bool, what: str) -> bool:
        if not condition:
            first = not self.problems
            self.problems.append(what)
            print(f"click check failed: {what}", file=sys.stderr, flush=True)
            if first:            # what the window looked like (with --shots) and held
                hidden = [t for t, shown in self.state.open_panels.items() if not shown]
                print(f"  hidden panels: {hidden or 'none'}; panel errors: "
                      f"{self.app.panels.panel_errors[-3:]}", file=sys.stderr, flush=True)
                self.screenshot("first-failure")
        return bool(condition)

    def exists(self, ref: str) -> bool:
        return self._item_id(ref) != 0

    def window(self, window_ref: str):
        """The imgui window (internal.Window) ``window_ref`` names, or None (no error)."""
        from imgui_bundle import imgui

        return self.ctx.window_info(window_ref, imgui.test_engine.TestOpFlags_.no_error).window

    def _window_soon(self, window_ref: str, frames: int = 20):
        """The window ``window_ref`` once it is drawn (a child window the panel shows
        again, e.g. the article after the lesson list, takes a frame or two)."""
        for _ in range(frames):
            window = self.window(window_ref)
            if window is not None:
                return window
            self.ctx.yield_()
        return None

    def scroll_y(self, window_ref: str) -> float:
        """The vertical scroll of a window or child window (e.g. the article)."""
        info = self.ctx.window_info(window_ref)
        return float(info.window.scroll.y) if info.window is not None else float("nan")

    def view_pixels(self):
        """The 3D view's pixels as the window shows them now (H, W, 3 uint8), or None."""
        import tempfile

        shot = Path(tempfile.mkdtemp(prefix="click-")) / "view.png"
        self.state.requests.screenshot = shot       # the window keeps the frame it writes
        self.ctx.yield_(2)
        rect, pixels = self.state.runtime.view.view_rect, self.app.last_pixels
        shot.unlink(missing_ok=True)
        shot.parent.rmdir()
        if rect is None or pixels is None:
            return None
        x0, y0, x1, y1 = (int(round(v)) for v in rect)
        return pixels[y0:y1, x0:x1].copy()

    def picture_changes(self, action, what: str, min_change: float = 1.0) -> None:
        """``action()`` changes the converged picture the view shows (mean absolute
        difference over the view, 0..255, at least ``min_change``)."""
        import numpy as np

        self.converged()
        before = _thumbnail(self.view_pixels())
        action()
        self.converged()
        self.settle_input(3)
        after = _thumbnail(self.view_pixels())
        if before is None or after is None:
            self.check(False, f"{what}: the view's picture could not be compared ("
                       f"{None if before is None else before.shape}, "
                       f"{None if after is None else after.shape})")
            return
        change = float(np.abs(before.astype(float) - after.astype(float)).mean())
        self.check(change >= min_change,
                   f"{what}: the picture changes (mean |difference| {change:.2f} of 255)")

    def screenshot(self, name: str) -> None:
        if self.shots is None:
            return
        # the window writes it after its next frame (a test runs on the engine's
        # thread, where no GL context is current: it must not draw itself)
        self.state.requests.screenshot = self.shots / f"{name}.png"
        self.ctx.yield_(2)

    def _panel_errors(self, after: str) -> None:
        errors = self.app.panels.panel_errors
        for text in errors[self._seen_errors:]:
            self.problems.append(f"after {after}: {text}")
        self._seen_errors = len(errors)


def _inside(info):
    """The centre of the item ``info`` (an engine item info) when the item is drawn whole
    inside its window (its clipped rectangle is its full one), else None."""
    from imgui_bundle import imgui

    full, clipped = info.rect_full, info.rect_clipped
    if (full.min.x, full.min.y, full.max.x, full.max.y) != \
            (clipped.min.x, clipped.min.y, clipped.max.x, clipped.max.y) \
            or full.max.x - full.min.x < 2.0 or full.max.y - full.min.y < 2.0:
        return None
    return imgui.ImVec2(0.5 * (full.min.x + full.max.x), 0.5 * (full.min.y + full.max.y))


def _thumbnail(pixels, size: int = 64):
    """``pixels`` sampled on a size x size grid (the view's image changes size with the
    view mode: a legend row under a split or a difference)."""
    import numpy as np

    if pixels is None or pixels.size == 0:
        return None
    rows = np.linspace(0, pixels.shape[0] - 1, size).astype(int)
    columns = np.linspace(0, pixels.shape[1] - 1, size).astype(int)
    return pixels[rows][:, columns]


def run_session(name: str, shots: Path | None = None) -> dict:
    from click_sessions import SESSIONS, small_error_measurement

    from explorer.gl.window import headless_available
    from explorer.ui.app import App
    from explorer.ui.window_options import WindowOptions

    session = SESSIONS[name]
    state = session.state()
    # glfw's null platform where it has one (no X server: presenting 1280×720 frames
    # through Xvfb was a fifth of a session's CPU time, BENCHMARKS.md "The suite in
    # minutes"); the engine drives imgui's input itself, so the clicks are the same, and
    # the window tests of tests/ui/ still open their windows under Xvfb
    app = App(state, WindowOptions(width=WINDOW[0], height=WINDOW[1], visible=False, vsync=False,
                                   persist_settings=False, test_engine=True,
                                   headless=headless_available()))
    small_error_measurement(app.state)
    labels = DrawnLabels()
    labels.install()
    clicks: dict = {}
    problems: list[str] = []
    start = time.monotonic()
    try:
        engine = app.test_engine

        def body(ctx) -> None:
            c = Clicks(app, ctx, problems, shots)
            c.labels = labels
            clicks["c"] = c
            session.run(c)

        exceptions = engine.add("click", name, body)
        while not engine.idle:
            c = clicks.get("c")
            if c is not None and not c.waiting:
                app.note_input()         # the engine's mouse and keys: a reader at work
            if not app.frame():
                if c is not None and c.expect_quit and app.state.requests.quit:
                    c.quit_seen, c.expect_quit = True, False
                    app.state.requests.quit = False
                    continue
                problems.append("the window closed")
                break
            if time.monotonic() - start > SESSION_TIMEOUT_S:
                problems.append(f"the session ran past {SESSION_TIMEOUT_S:g} s")
                break
        outcome = engine.results()[0]
        problems += exceptions
    finally:
        app.close()
    c = clicks.get("c")
    report = {"session": name, "passed": outcome.passed and not problems,
              "status": outcome.status, "clicks": len(c.controls) if c else 0,
              "controls": sorted(set(c.controls)) if c else [],
              "problems": list(dict.fromkeys(problems)),
              "seconds": round(time.monotonic() - start, 1)}
    return report


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("session")
    parser.add_argument("--shots", type=Path, default=None,
                        help="write the screenshots the session takes to this folder")
    args = parser.parse_args()
    if args.shots is not None:
        args.shots = args.shots.resolve()
    # what the window writes where it was started (File/Screenshot) goes to a folder
    # of its own
    os.chdir(tempfile.mkdtemp(prefix="click-session-"))
    if args.shots is not None:
        args.shots.mkdir(parents=True, exist_ok=True)
    report = run_session(args.session, args.shots)
    print(json.dumps(report))
    return 0 if report["passed"] else 1


if __name__ == "__main__":
    sys.exit(main())
