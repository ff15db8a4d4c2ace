"""Dear ImGui Test Engine (``imgui.test_engine``, shipped in imgui-bundle) on the explorer's
own glfw + imgui loop: tests that find items by label and click, drag and type in the
real window (tests/click_app.py drives the whole window with it).

The engine runs each test function on a coroutine thread of its own and switches to it
from inside ``ImGui::NewFrame`` and ``ImGui::EndFrame`` (its context hooks). A test
function is Python, so that thread needs the GIL while the main thread waits in those
two calls. hello_imgui's runner releases the GIL around them in C++; this loop is Python,
so :class:`TestEngine` calls the two C++ functions through ``ctypes``, which releases
the GIL for the length of a foreign call (the bindings' own ``imgui.new_frame`` keeps
it, and the first queued test would dead-lock the window).

Only a window built with a test engine uses these calls; the explorer's normal loop
calls imgui through its bindings.
"""

from __future__ import annotations

import ctypes
from dataclasses import dataclass, field

_NEW_FRAME = "_ZN5ImGui8NewFrameEv"     # ImGui::NewFrame()
_RENDER = "_ZN5ImGui6RenderEv"          # ImGui::Render()


def _gil_free(symbol: str):
    """``symbol`` of imgui-bundle's extension module as a ctypes function (CDLL: the GIL
    is released while it runs)."""
    from imgui_bundle import _imgui_bundle

    function = getattr(ctypes.CDLL(_imgui_bundle.__file__), symbol)
    function.restype, function.argtypes = None, []
    return function


@dataclass
class TestOutcome:
    """One finished test: its group/name, the engine's status name and, for a failure,
    what went wrong (the engine's log is printed to the terminal as it runs)."""

    name: str
    status: str
    problems: list[str] = field(default_factory=list)

    @property
    def passed(self) -> bool:
        return self.status == "success" and not self.problems


class TestEngine:
    """An ImGuiTestEngine bound to the current imgui context.

    ``speed``: "fast" (the mouse teleports, no waits: CI), "normal" (watchable) or
    "cinematic"."""

    def __init__(self, imgui_context, speed: str = "fast") -> None:
        from imgui_bundle import imgui

        te = imgui.test_engine
        self._te = te
        self.engine = te.create_context()
        io = te.get_io(self.engine)
        io.config_verbose_level = te.TestVerboseLevel.warning
        io.config_verbose_level_on_error = te.TestVerboseLevel.debug
        io.config_log_to_tty = True
        io.config_run_speed = {"fast": te.TestRunSpeed.fast, "normal": te.TestRunSpeed.normal,
                               "cinematic": te.TestRunSpeed.cinematic}[speed]
        io.config_no_throttle = True
        io.config_restore_focus_after_tests = False
        io.config_capture_enabled = False
        # a session is one long test (many clicks in one window): the engine's watchdog
        # would otherwise stop it after a minute
        io.config_watchdog_warning = 600.0
        io.config_watchdog_kill_test = 1800.0
        io.config_watchdog_kill_app = 3600.0
        te.start(self.engine, imgui_context)
        self._new_frame = _gil_free(_NEW_FRAME)
        self._render = _gil_free(_RENDER)
        self._tests: list[tuple[str, object, list[str]]] = []

    # -- the frame --------------------------------------------------------------------
    def new_frame(self) -> None:
        self._new_frame()

    def render(self) -> None:
        self._render()

    def post_swap(self) -> None:
        self._te.post_swap(self.engine)

    # -- tests ------------------------------------------------------------------------
    def add(self, group: str, name: str, function) -> list[str]:
        """Register and queue ``function(ctx)`` as test ``group/name``; returns the list
        its checks append their failures to (:meth:`results` reports them)."""
        test = self._te.register_test(self.engine, group, name)
        problems: list[str] = []

        def run(ctx) -> None:
            try:
                function(ctx)
            except Exception as exc:      # the engine would report it only as "error"
                import traceback

                problems.append(f"{type(exc).__name__}: {exc}")
                traceback.print_exc()
                raise

        test.test_func = run
        self._tests.append((f"{group}/{name}", test, problems))
        self._te.queue_test(self.engine, test)
        return problems

    @property
    def idle(self) -> bool:
        """No test queued or running."""
        return self._te.is_test_queue_empty(self.engine) and not \
            self._te.get_io(self.engine).is_running_tests

    def results(self) -> list[TestOutcome]:
        outcomes = []
        for name, test, problems in self._tests:
            status = test.output.status
            outcomes.append(TestOutcome(name, self._te.get_status_name(status).lower(),
                                        list(problems)))
        return outcomes

    def stop(self) -> None:
        """Stop the engine (before the imgui context is destroyed)."""
        self._te.stop(self.engine)

    def destroy(self) -> None:
        """Free the engine (after the imgui context is destroyed)."""
        self._te.destroy_context(self.engine)
