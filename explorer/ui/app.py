"""The explorer window shell: one glfw window, imgui panels over one AppState, and the
frame loop; the pipelines are the :class:`~explorer.ui.controller.PipelineController`'s.

Each frame the shell polls input, hands the state to the controller with the frame
budget (``AppState.frame_budget_ms`` of pipeline work: a change renders over several
frames, the view showing the light grow, "propagating 5/8"), draws the panels and the
view (explorer/ui/view_composer.py composes what it shows from the sides' pictures), and
swaps. When nothing changed, no job runs and nothing animates, the loop waits for events
instead of drawing (``wait_when_idle``); input draws at once. While the mouse moves the
camera (or the gizmo an object) and while the scene's animation or fly-through plays
(explorer/ui/animation.py, ticked before the controller's update) the controller renders
at a reduced size, and at full size once it stops.

Drive it from code (tests, scripts)::

    app = App(width=800, height=600, visible=False)
    app.state.set_corrections(propagation_4pi=False)
    app.settle()                     # frames until the picture has converged
    app.screenshot("shot.png")       # the whole window, panels included
    app.close()
"""

from __future__ import annotations

import sys
import time
import traceback
from dataclasses import astuple
from pathlib import Path
from typing import Callable

import numpy as np

from explorer.gl.window import Window
from explorer.lpv.settings import PRESETS, Settings, preset_name
from explorer import stop_signals
from explorer.ui import animation, persist, theme
from explorer.ui.images import write_png
from explorer.ui.state import AppState, default_screenshot_path, fit_window_size

_MIN_RENDER_SIZE = 16
_MAX_RENDER_SIZE = 2048
_RESIZE_SETTLE_S = 0.15       # re-render at a new view size once resizing pauses this long
_LAYOUT_FRAMES = 2          # frames before the View panel's size is trusted
INTERACTION_SETTLE_S = 0.2
"""After the last wheel step or key move the camera counts as moving this much longer."""
FRAMES_AFTER_INPUT = 2
"""Frames drawn after input or a change before the loop may wait (imgui settles hover
and click states over a frame or two)."""
IDLE_TIMEOUT_S = 0.5
"""An idle loop wakes this often without input (shader files, the Error panel's delay);
it draws only if something changed."""
MESSAGE_SHOWN_S = 20.0        # the status line shows the last message this long
DRAG_FPS = 15.0
"""Frame rate aimed at while the camera is dragged (issue #10): the pipelines get what a
frame at this rate leaves after the window's own drawing, and render at the size that
fits (explorer/ui/controller.py DRAG_SCALES)."""
MIN_DRAG_BUDGET_MS = 4.0
PROGRESS_REDRAW_S = 1.0
"""While a job runs and no new picture or input arrives, the window draws this often
(the progress label; each drawing costs the job about as much as a propagation step on
llvmpipe)."""
SETTLE_FRAMES = 100000


class App:
    def __init__(self, state: AppState | None = None, *, width: int | None = None,
                 height: int | None = None,
                 visible: bool = True, vsync: bool = True, persist_settings: bool = True,
                 pipeline_class: Callable | None | object = ...,
                 wait_when_idle: bool | None = None,
                 idle_timeout_s: float = IDLE_TIMEOUT_S, test_engine: bool = False,
                 headless: bool = False) -> None:
        """``pipeline_class``: the Pipeline class (default: explorer.lpv.pipeline's), or
        None for a window without a pipeline (panels only: the window tests).
        ``wait_when_idle``: wait for events instead of drawing when nothing changed
        (default: for a visible window; a hidden one is scripted and draws every
        :meth:`frame`); ``idle_timeout_s``: the longest such wait. ``test_engine``: start
        Dear ImGui Test Engine in the window (:attr:`test_engine` queues click tests,
        explorer/ui/test_engine.py). ``headless``: no display needed (glfw's null
        platform with EGL, :class:`~explorer.gl.window.Window`): exports and scripts."""
        self.state = state or AppState()
        self.persist_settings = persist_settings
        self.wait_when_idle = visible if wait_when_idle is None else bool(wait_when_idle)
        self.idle_timeout_s = float(idle_timeout_s)
        # the settings there are read even when nothing can be saved
        read_settings = persist_settings and state is None
        if persist_settings:
            unwritable = persist.writable_config_dir()
            if unwritable:      # run on, saving nothing: said once, never a failed start
                print(f"lpv-explorer: {unwritable}", file=sys.stderr)
                self.state.notify(unwritable, "warning")
                self.persist_settings = False
        if read_settings:
            problem = persist.load_state(self.state)
            if problem:
                print(f"lpv-explorer: {problem}", file=sys.stderr)
                self.state.notify(problem, "warning")
        # The window opens at the given size, else at the size it had when it was closed
        # (the default the first time), shrunk to fit the monitor's work area and
        # centred on it: a size saved on a larger screen, or the default on a small one,
        # would cut off the tool column.
        saved_w, saved_h = self.state.window_size
        size, position = (width or saved_w, height or saved_h), None
        if (width is None or height is None) and not headless:
            from explorer.gl.window import work_area
            from explorer.ui.state import fit_work_area

            size, position = fit_work_area(size, work_area() if visible else None)
        self.window = Window(*size, visible=visible and not headless, vsync=vsync,
                             position=position, headless=headless)
        self.ctx = self.window.ctx
        rt = self.state.runtime
        rt.services.gl_problem = self.window.gl_problem
        rt.services.gl_renderer = str(self.ctx.info.get("GL_RENDERER", "")) if self.ctx else ""
        if rt.services.gl_problem:
            print(f"lpv-explorer: {rt.services.gl_problem}", file=sys.stderr)
        if pipeline_class is ...:
            from explorer.lpv.pipeline import Pipeline as pipeline_class
        from explorer.ui.controller import PipelineController

        self.controller = PipelineController(
            self.ctx, None if rt.services.gl_problem else pipeline_class)
        if pipeline_class is None and not rt.services.gl_problem:
            rt.frame.pipeline_error = ("no LPV pipeline attached (App(pipeline_class=None)): the "
                                 "panels work, the view stays empty")
        self._pending_size: tuple | None = None
        self._capture = False
        self._quiet = False           # the last frame found nothing to do: wait next time
        self._draws_pending = 0       # frames still to draw after input or a change
        self._seen: tuple | None = None   # the state as the last drawn frame left it
        self._drawn_at = 0.0              # time.monotonic() of the last drawn frame
        self._shown_result = None     # A's result the title was made for
        self._interacted = False      # the last update ran while the camera moved
        self._input_at = time.monotonic()     # the last input (the controller's budget)
        self.status = None
        """The controller's status of the last frame (explorer.ui.controller)."""
        self.ui_ms = 30.0
        """The window's own time per drawn frame (smoothed), besides pipeline work."""
        self.drew_change = False
        """The last drawn frame's panels changed the state (a lesson step applied, a
        button pressed): the pipelines have not seen it yet, whatever their status."""
        self.frames_skipped = 0
        self.last_wait_s = 0.0
        """How long the last frame() waited for events (an idle window)."""
        """frame() calls that found nothing to do and drew nothing."""
        self._docked: dict[str, bool] = {}
        """Panel title -> whether it was docked when last drawn (its background: _draw_ui)."""
        self.draw_phases_ms: dict[str, float] = {}
        """The last drawn frame's drawing by phase (:meth:`frame`), in milliseconds."""
        self.last_pixels: np.ndarray | None = None
        self.panel_errors: list[str] = []
        """Every panel failure so far (an exception its gui function raised)."""
        self._init_imgui(test_engine)
        self.test_engine = self._imgui.test_engine
        # SIGTERM / SIGHUP: quit as the Quit item does (close() saves); a second: at once
        self._restore_signals = stop_signals.calling(self._quit_on_signal)

    def _quit_on_signal(self, signum: int) -> None:
        self.state.requests.quit = True

    # -- setup ---------------------------------------------------------------------------
    def _init_imgui(self, test_engine: bool = False) -> None:
        from imgui_bundle import imgui

        from explorer.ui.formulas import FormulaCache
        from explorer.ui.imgui_host import ImguiHost
        from explorer.ui.overlays.compositor import Compositor
        from explorer.ui.textures import UiTextures

        self._imgui = ImguiHost(self.window, test_engine=test_engine)
        io = imgui.get_io()
        io.config_flags |= imgui.ConfigFlags_.docking_enable
        io.config_flags |= imgui.ConfigFlags_.nav_enable_keyboard
        self._layout_file = persist.layout_path()
        # imgui never opens the layout file itself (it would block on a FIFO and write in
        # place): the app reads it safely and writes it atomically (persist.py).
        io.set_ini_filename("")
        self._layout_loaded = False
        if self.persist_settings:
            # imgui asserts on a layout it cannot use: checked first, set aside if bad
            layout, problem = persist.load_layout(self._layout_file)
            if problem:
                print(f"lpv-explorer: {problem}", file=sys.stderr)
                self.state.notify(problem, "warning")
            if layout:
                imgui.load_ini_settings_from_memory(layout)
                self._layout_loaded = True
        from explorer.ui.layout import PANELS

        titles = [panel.title for panel in PANELS]
        # Rebuild the default layout on the first run and whenever the panel set changed
        # (a panel the saved layout does not know would otherwise float on its own).
        self._needs_layout = not (self._layout_loaded
                                  and sorted(self.state.layout_panels) == sorted(titles))
        self.state.layout_panels = titles
        theme.apply_style(self.window.content_scale)
        from explorer.ui import fonts

        self.state.runtime.services.fonts = fonts.load(io, 15.0)   # Roboto + math symbols
        self._imgui.start_backends()
        rt = self.state.runtime
        rt.services.textures = UiTextures(self.ctx)
        rt.services.compositor = Compositor(self.ctx)     # the View panel's in-scene overlays
        if not rt.services.gl_problem:
            from explorer.ui.view_composer import ViewComposer

            rt.services.composer = ViewComposer(self.ctx, self.controller.programs)
        rt.services.formulas = FormulaCache(rt.services.textures,
                                            font_size=17.0 * self.window.content_scale)
        self._markdown_ctx = theme.markdown_context()
        rt.services.markdown_ready = self._markdown_ctx is not None
        try:
            from imgui_bundle import portable_file_dialogs as pfd

            rt.services.file_dialog_available = bool(pfd.settings.available())
        except Exception:  # noqa: BLE001 - no zenity/kdialog: hide the browse button
            rt.services.file_dialog_available = False

    # -- the loop ------------------------------------------------------------------------
    def run(self, frames: int | None = None, screenshot: Path | None = None,
            converged: bool = True) -> int:
        """Run until the window closes (or for ``frames`` frames, then, with
        ``screenshot``, until the picture has converged, and write the window to it;
        ``converged`` False: write the frame after ``frames`` as it is, its view saying
        "propagating k/N" if it is still converging). Returns an exit status."""
        count = 0
        while self.frame():
            count += 1
            if frames is not None and count >= frames:
                break
        if screenshot is not None:
            if count == 0:
                print("lpv-explorer: no frame was drawn, no screenshot written",
                      file=sys.stderr)
                return 1
            began, waited = time.monotonic(), 0
            if converged:
                print("lpv-explorer: waiting for the converged frame (--no-wait writes "
                      "the frame as it is)", flush=True)
                waited = self.settle()
                if waited is None:
                    print("lpv-explorer: the window closed before the frame converged, "
                          "no screenshot written", file=sys.stderr)
                    return 1
            self.frame(capture=True)
            write_png(self.last_pixels, screenshot)
            progress = self.state.runtime.frame.progress.get("A")
            if converged:
                print(f"lpv-explorer: wrote {screenshot} (converged after {count} + "
                      f"{waited} frames, {time.monotonic() - began:.1f} s of waiting)")
            else:
                print(f"lpv-explorer: wrote {screenshot} after {count} frames ("
                      + (f"not converged: {progress}" if progress else "converged") + ")")
        return 0

    def settle(self, max_frames: int = SETTLE_FRAMES) -> int | None:
        """Draw frames until no job runs, no background task works, the camera is still
        and the last frame's panels changed nothing the pipelines have not seen yet
        (scripts and tests: the picture has converged). Returns the frames drawn (at
        least 1), or None if the window closed first. A playing animation never settles:
        pause it first."""
        for drawn in range(1, max_frames + 1):
            if not self.frame(force=True):
                return None
            status = self.status
            if self.drew_change:
                continue                 # a step or a button changed the settings
            if status is not None and not status.active and not self._interacted:
                return drawn             # a frame that found nothing left to do
            if status is None and self.state.runtime.frame.frame_index > _LAYOUT_FRAMES:
                return drawn         # no pipeline (or no GL): nothing to wait for
        return max_frames

    def frame(self, capture: bool = False, force: bool = False) -> bool:
        """Process events, advance the pipelines within the frame budget and draw one
        frame; with nothing to do (no input, no change, no work, no animation) an idle
        window waits for events instead and draws nothing (``force``: draw anyway).
        False once the window should close.

        ``capture``: keep the drawn frame (panels included) in :attr:`last_pixels`."""
        from imgui_bundle import imguizmo

        force = force or capture or not self.wait_when_idle
        self.last_wait_s = 0.0
        if self._quiet and not force and not self.window.events and \
                self._seen == self._fingerprint():
            waited = time.perf_counter()
            self.window.poll_events(timeout=self._idle_timeout())
            self.last_wait_s = time.perf_counter() - waited
        start = time.perf_counter()         # the frame's time, without the idle wait
        self.window.poll_events()
        if self.window.should_close() or self.state.requests.quit:
            return False
        self._handle_drops()
        if self.window.minimised:
            # Nothing to draw into: skip GL work entirely and sleep until an event.
            self.window.poll_events(timeout=0.1)
            return True
        rt = self.state.runtime
        events = self.window.take_events()
        if events:
            self._input_at = time.monotonic()
        self.status = None
        if not rt.services.gl_problem:
            animation.tick(self.state)       # playing paths and fly-through: new Settings
        changed = self._seen != self._fingerprint()
        if not rt.services.gl_problem:
            self._update_pipelines()
        status = self.status
        worked = status is not None and status.active
        must_draw = (force or events or changed or rt.redraw or self._draws_pending
                     or self._message_expired() or (status is not None and (
                         status.published or status.failures > 0)))
        if not must_draw and not worked:
            self._quiet = True              # nothing to do: wait for events next time
            self.frames_skipped += 1
            return True
        if not must_draw and time.monotonic() - self._drawn_at < PROGRESS_REDRAW_S:
            # a job runs with nothing new to show: its time goes to the job (input is
            # still read between budgets); the progress label is redrawn this often.
            # The next frame goes on with it, never waiting for events.
            self._quiet = False
            self.frames_skipped += 1
            return True
        rt.redraw, rt.audit_wanted = False, "off"   # what is drawn now asks again
        before_draw = self._fingerprint()
        drawing = time.perf_counter()
        self._imgui.new_frame()
        imguizmo.im_guizmo.begin_frame()
        self._draw_ui()
        from explorer.ui import widgets

        rt.redraw = rt.redraw or widgets.animating()
        built = time.perf_counter()
        self._imgui.render(self.ctx, theme.CLEAR_COLOUR)
        self._after_render(capture)
        self.window.swap_buffers()
        self._imgui.post_swap()
        # the window's own drawing, apart from the pipeline's work (bench --interactive):
        # the panels built on the CPU, then imgui's draw lists rendered and swapped (a
        # software renderer rasterises them by the swap)
        self.draw_phases_ms = {"panels": (built - drawing) * 1e3,
                               "render_and_swap": (time.perf_counter() - built) * 1e3}
        rt.frame.frame_index += 1
        rt.frame.frame_ms = (time.perf_counter() - start) * 1000.0
        work_ms = status.work_ms if status is not None else 0.0
        # the window's own cost per frame (panels, drawing, swap), smoothed
        self.ui_ms += 0.2 * (max(rt.frame.frame_ms - work_ms, 0.0) - self.ui_ms)
        self._draws_pending = FRAMES_AFTER_INPUT if (events or changed) else max(
            self._draws_pending - 1, 0)
        self._seen = self._fingerprint()
        self.drew_change = self._seen != before_draw
        self._drawn_at = time.monotonic()
        self._quiet = not (worked or rt.redraw or self._draws_pending or self._interacting())
        return True

    def note_input(self) -> None:
        """Input arrived that the window's events do not show (Dear ImGui Test Engine's
        simulated mouse and keys): the pipelines keep to the frame budget, as for a
        reader's input, instead of the quiet budget of a window nobody touches."""
        self._input_at = time.monotonic()

    def _interacting(self) -> bool:
        """The camera or an object is being moved (a drag, the gizmo, a wheel step or a
        fly key a moment ago) or the animation plays (its paths move the light and objects,
        the fly-through the camera): the pipelines render at the drag's reduced size, a
        frame in flight finishes before the next starts, and the loop does not idle."""
        rt = self.state.runtime
        return (rt.view.interaction.active(time.monotonic(), INTERACTION_SETTLE_S)
                or (rt.services.animation is not None and rt.services.animation.active))

    def _idle_timeout(self) -> float:
        """How long an idle loop may wait: the idle timeout, or less when the status
        line's message is due to disappear sooner or a camera move settles sooner (its
        full-size frame starts then)."""
        timeout = self.idle_timeout_s
        interaction = self.state.runtime.view.interaction
        if not interaction.held:      # a camera move settling: the full size follows then
            settles = interaction.moved_at + INTERACTION_SETTLE_S - time.monotonic()
            if settles > 0:
                timeout = min(timeout, settles + 0.01)
        messages = self.state.messages
        if messages and messages[-1].level != "error":
            left = messages[-1].created + MESSAGE_SHOWN_S - time.monotonic()
            if left > 0:
                timeout = min(timeout, left + 0.05)
        return max(timeout, 0.0)

    def _message_expired(self) -> bool:
        """The status line shows a message whose time is up: draw it away."""
        messages = self.state.messages
        if not messages or messages[-1].level == "error":
            return False
        created = messages[-1].created
        return self._drawn_at - created < MESSAGE_SHOWN_S <= time.monotonic() - created

    def _fingerprint(self) -> tuple:
        """What the window shows depends on besides input and the pipelines' work, so
        that a script or test that changes the state between frames gets it drawn."""
        s = self.state
        return (s.settings, s.compare_settings, s.compare_overrides, s.view_mode,
                s.view_buffer, s.split_position, s.expose_sides_separately,
                s.difference_scale, s.difference_colour_map, s.follow_view_size,
                s.render_scale, s.frame_budget_ms, s.progressive, astuple(s.inspect),
                astuple(s.overlays), tuple(s.open_panels.items()), s.lesson_id,
                s.lesson_step, s.plot_tab, len(s.messages), astuple(s.requests),
                s.runtime.frame.side_exposures)

    def screenshot(self, path: str | Path) -> Path:
        """Draw a frame and write it, panels included, to ``path`` (PNG)."""
        self.frame(capture=True)
        path = Path(path)
        write_png(self.last_pixels, path)
        return path

    def close(self) -> None:
        from imgui_bundle import imgui

        if self.persist_settings:
            try:
                if not self.window.minimised:
                    self.state.window_size = fit_window_size(self.window.size)
                self._keep_settings_that_ran()
                persist.save_state(self.state)
            except OSError as exc:
                print(f"lpv-explorer: could not save settings: {exc}", file=sys.stderr)
        rt = self.state.runtime
        for task in rt.services.tasks:
            task.release()
        rt.services.tasks.clear()
        for owned in (rt.services.composer, rt.services.textures, rt.services.compositor):
            if owned is not None:
                owned.release()
        rt.services.composer = None
        rt.frame.pictures = {}
        self.controller.release()
        if self.persist_settings:
            try:
                persist.save_layout(imgui.save_ini_settings_to_memory(), self._layout_file)
            except OSError as exc:
                print(f"lpv-explorer: could not save the layout: {exc}", file=sys.stderr)
        if self._markdown_ctx is not None:
            from imgui_bundle import rich_md

            rich_md.destroy_context(self._markdown_ctx)
            self._markdown_ctx = None
        self._imgui.shutdown()
        self.window.close()
        self._restore_signals()

    def _keep_settings_that_ran(self) -> None:
        """Before saving: settings the pipeline refused are not written back; the last
        settings that ran take their place (the defaults when none ran)."""
        if self.controller.failed_settings == self.state.settings:
            self.state.settings = self.controller.ran_settings or Settings()

    # -- pipelines -----------------------------------------------------------------------
    def settings_for(self, side: str) -> Settings:
        """The Settings side ``side`` ("A" or "B") shows (the controller's)."""
        return self.controller.settings_for(self.state, side)

    def _follow_view_size(self) -> bool:
        """Keep the render size at the View panel's pixels; False while the size is
        not known yet (the first frames), so the first run already has the right size."""
        state, rt = self.state, self.state.runtime
        if not state.follow_view_size:
            return True
        vw, vh = rt.view.view_size
        if rt.frame.frame_index < _LAYOUT_FRAMES:
            return False                # the dock layout settles in its first frames
        if vw < _MIN_RENDER_SIZE or vh < _MIN_RENDER_SIZE:
            return True                 # the view panel is hidden: keep the stored size
        size = (int(np.clip(vw * state.render_scale, _MIN_RENDER_SIZE, _MAX_RENDER_SIZE)),
                int(np.clip(vh * state.render_scale, _MIN_RENDER_SIZE, _MAX_RENDER_SIZE)))
        current = (state.settings.width, state.settings.height)
        if size == current:
            self._pending_size = None
            return True
        now = time.monotonic()
        if rt.frame.result is None or (self._pending_size and self._pending_size[0] == size
                                 and now - self._pending_size[1] >= _RESIZE_SETTLE_S):
            state.update(width=size[0], height=size[1])
            self._pending_size = None
        elif not self._pending_size or self._pending_size[0] != size:
            self._pending_size = (size, now)
        return True

    def _update_pipelines(self) -> None:
        """Hand the state to the controller with the frame budget; publish what the view
        needs to show each side."""
        state, rt = self.state, self.state.runtime
        if self.controller.pipeline_class is None:
            return
        if state.requests.open_scene:
            self._open_scene(state.requests.open_scene)
            state.requests.open_scene = None
            if state.requests.scene_overrides:     # run --light / --camera, after the reset
                state.update(**state.requests.scene_overrides)
                state.requests.scene_overrides = None
        if not self._follow_view_size():
            return
        drag_budget = max(1000.0 / DRAG_FPS - self.ui_ms, MIN_DRAG_BUDGET_MS)
        self._interacted = self._interacting()
        self.status = self.controller.update(
            state, state.frame_budget_ms,
            need_audit=rt.audit_wanted, interacting=self._interacted,
            drag_budget_ms=drag_budget, draw_ms=self.ui_ms,
            quiet_s=self._quiet_s(), input_pending=self._input_pending)
        rt.frame.progress = dict(self.status.labels)
        rt.frame.displays = {side: self.controller.side_display(state, side)
                       for side in rt.frame.pictures}
        if rt.frame.result is not None and rt.frame.result is not self._shown_result:
            self._shown_result = rt.frame.result
            self._update_title()

    def _quiet_s(self) -> float:
        """Seconds since the last input, as the controller's quiet budget reads them; 0
        when this frame will be drawn anyway for the progress label (a frame that draws
        keeps to the frame budget: its work and its drawing stay one frame's worth)."""
        if time.monotonic() - self._drawn_at >= PROGRESS_REDRAW_S:
            return 0.0
        return time.monotonic() - self._input_at

    def _input_pending(self) -> bool:
        """Whether input arrived since this frame began (the controller asks between
        units of a quiet frame's longer budget, and stops at the frame budget if so)."""
        self.window.poll_events()
        return self.window.events > 0

    def _open_scene(self, name_or_path: str) -> None:
        if name_or_path == self.state.settings.scene:
            return
        # A new scene starts from its own camera, lights and objects.
        self.state.update(scene=str(name_or_path), camera=None, light=None, light_flux=None,
                          lights=None, object_transforms=(), camera_fov=None,
                          light_kind=None)
        self.state.notify(f"opening {name_or_path}")

    # -- UI ------------------------------------------------------------------------------
    def _draw_ui(self) -> None:
        from imgui_bundle import imgui

        from explorer.ui.layout import PANELS, build_default_layout, window_class

        state = self.state
        self._main_menu()
        viewport = imgui.get_main_viewport()
        dock_id = imgui.get_id("lpv-dockspace")
        size = viewport.work_size
        # a window not yet sized (some glfw and imgui-bundle versions report 0 for the first
        # frame) builds its layout on the next frame: the dock builder asserts on size 0
        if (self._needs_layout or state.requests.reset_layout) and size.x > 0 and size.y > 0:
            build_default_layout(dock_id, size)
            self._needs_layout = False
            state.requests.reset_layout = False
        imgui.dock_space_over_viewport(dock_id, viewport)
        if state.runtime.services.gl_problem:
            self._gl_problem_window()
            return
        requested = state.requests.focus_panel
        focus = (requested,) if isinstance(requested, str) else tuple(requested or ())
        # One panel a frame: a dock node selects the tab of the window that holds the
        # keyboard focus when its tab bar updates (next frame), so of several panels
        # focused in one frame only the last would come forward (lesson 12's Inspect
        # lost to Error). The others wait for the following frames.
        from explorer.ui.lesson_panel import hidden_panels

        # the reader's mode: the panels the step does not use are hidden
        hidden = hidden_panels(state, (panel.title for panel in PANELS))
        for panel in PANELS:
            if panel.title in focus and not self._needs_layout:
                state.open_panels[panel.title] = True
            if not state.open_panels.get(panel.title, True) or panel.title in hidden:
                continue
            if focus and panel.title == focus[0] and not self._needs_layout:
                imgui.set_next_window_focus()
            if panel.window_class:
                imgui.set_next_window_class(window_class(panel))
            if not panel.padding:
                imgui.push_style_var(imgui.StyleVar_.window_padding, (2.0, 2.0))
            # A docked panel draws no background of its own: the frame's clear paints the
            # same colour (theme.CLEAR_COLOUR). On a software renderer each full-window
            # layer of fill is a large part of a frame (the panels' backgrounds cover the
            # whole window, about 1.5 Mpx at 1600×960); imgui skips transparent fills. A
            # floating panel keeps its background (docked: as of the last frame).
            docked = self._docked.get(panel.title, False)
            if docked:
                imgui.push_style_color(imgui.Col_.window_bg, theme.DOCKED_WINDOW_BG)
            expanded, still_open = imgui.begin(panel.title, True)
            if docked:
                imgui.pop_style_color()
            self._docked[panel.title] = imgui.is_window_docked()
            if not panel.padding:
                imgui.pop_style_var()
            if expanded:
                stacks = imgui.internal.ErrorRecoveryState()
                imgui.internal.error_recovery_store_state(stacks)
                try:
                    panel.gui(state)
                except Exception as exc:  # noqa: BLE001 - one broken panel, not the app
                    self._panel_failed(panel.title, exc)
                    _recover_stacks(stacks)
            imgui.end()
            state.open_panels[panel.title] = bool(still_open)
        if focus and not self._needs_layout and state.requests.focus_panel is requested:
            state.requests.focus_panel = focus[1:] or None   # (a panel may have asked anew)
        if imgui.is_key_pressed(imgui.Key.f12, False):
            state.requests.screenshot = default_screenshot_path()
        self._file_dialog()

    def _panel_failed(self, title: str, exc: Exception) -> None:
        text = f"panel {title}: {type(exc).__name__}: {exc}"
        self.panel_errors.append(text)
        if not self.state.messages or self.state.messages[-1].text != text:
            self.state.notify(text, "error")
            print(f"lpv-explorer: {text}", file=sys.stderr)
            traceback.print_exception(exc, file=sys.stderr)

    def _main_menu(self) -> None:
        from imgui_bundle import imgui

        from explorer.ui.layout import PANELS

        state = self.state
        if not imgui.begin_main_menu_bar():
            return
        if imgui.begin_menu("File"):
            if imgui.menu_item_simple("Open mesh…", enabled=bool(
                    state.runtime.services.file_dialog_available)):
                state.requests.open_file_dialog = True
            if imgui.menu_item_simple("Save scene as…"):
                state.requests.save_scene_dialog = True
            if imgui.menu_item_simple("Screenshot", "F12"):
                state.requests.screenshot = default_screenshot_path()
            imgui.separator()
            if imgui.menu_item_simple("Quit"):
                state.requests.quit = True
            imgui.end_menu()
        if imgui.begin_menu("Presets"):
            for side in ("A", "B"):
                for name in PRESETS:
                    if imgui.menu_item_simple(f"{side}: {name}"):
                        state.apply_preset(name, compare=side == "B")
            imgui.end_menu()
        if imgui.begin_menu("Windows"):
            if imgui.menu_item_simple("Reader's mode", selected=state.reader_mode):
                state.reader_mode = not state.reader_mode
            imgui.separator()
            for panel in PANELS:
                shown = state.open_panels.get(panel.title, True)
                if imgui.menu_item_simple(panel.title, selected=shown):
                    state.open_panels[panel.title] = not shown
            imgui.separator()
            if imgui.menu_item_simple("Reset layout"):
                state.requests.reset_layout = True
                for panel in PANELS:
                    state.open_panels[panel.title] = True
            imgui.end_menu()
        if state.messages:
            from explorer.ui.widgets import LEVEL_COLOURS

            last = state.messages[-1]
            if time.monotonic() - last.created < 20.0 or last.level == "error":
                text = last.text if len(last.text) < 110 else last.text[:107] + "…"
                imgui.same_line(max(imgui.get_window_width() - imgui.calc_text_size(text).x
                                    - 16, 300))
                imgui.text_colored(LEVEL_COLOURS.get(last.level), text)
        imgui.end_main_menu_bar()

    def _gl_problem_window(self) -> None:
        from imgui_bundle import imgui

        from explorer.ui.widgets import ERROR

        viewport = imgui.get_main_viewport()
        imgui.set_next_window_pos(viewport.get_center(), imgui.Cond_.always, (0.5, 0.5))
        imgui.set_next_window_size((min(viewport.size.x * 0.8, 720), 0))
        imgui.begin("OpenGL 4.3 needed", None, imgui.WindowFlags_.no_collapse
                    | imgui.WindowFlags_.no_docking)
        imgui.text_colored(ERROR, "This GL driver cannot run the LPV pipeline.")
        imgui.text_wrapped(self.state.runtime.services.gl_problem or "")
        imgui.text_wrapped("Run `lpv-explorer doctor` for details.")
        if imgui.button("Quit"):
            self.state.requests.quit = True
        imgui.end()

    def _file_dialog(self) -> None:
        state, rt = self.state, self.state.runtime
        if state.requests.open_file_dialog:
            state.requests.open_file_dialog = False
            if rt.services.file_dialog_available and rt.services.file_dialog is None:
                from imgui_bundle import portable_file_dialogs as pfd

                rt.services.file_dialog = pfd.open_file(
                    "Open a mesh or a scene file", str(Path.home()),
                    ["Meshes and scene files",
                     "*.obj *.ply *.stl *.glb *.gltf *.off *.toml", "All files", "*"])
        if state.requests.save_scene_dialog:
            state.requests.save_scene_dialog = False
            from explorer.ui.scene_save import SAVE_FILTERS, default_save_path, save_current_scene

            if not rt.services.file_dialog_available:     # no dialog here: a new file beside us
                save_current_scene(state, default_save_path(state, fresh=True))
            elif rt.services.file_dialog is None:
                from imgui_bundle import portable_file_dialogs as pfd

                rt.services.file_dialog = pfd.save_file(
                    "Save the scene", str(default_save_path(state)), SAVE_FILTERS)
        if rt.services.file_dialog is not None and rt.services.file_dialog.ready(0):
            chosen = rt.services.file_dialog.result()
            saving = not isinstance(chosen, list)      # save_file gives one path (text)
            rt.services.file_dialog = None
            if saving and chosen:
                from explorer.ui.scene_save import save_current_scene

                save_current_scene(state, chosen)
            elif chosen:
                state.mesh_path = chosen[0]
                state.requests.open_scene = chosen[0]

    def _handle_drops(self) -> None:
        dropped = self.window.dropped_paths
        while dropped:
            path = dropped.popleft()
            self.state.mesh_path = str(path)
            self.state.requests.open_scene = str(path)

    def _after_render(self, capture: bool) -> None:
        request = self.state.requests.screenshot
        if capture or request is not None:
            self.last_pixels = self.window.read_pixels()
        if request is not None:
            self.state.requests.screenshot = None
            try:
                write_png(self.last_pixels, request)
                self.state.notify(f"screenshot written to {request}")
            except OSError as exc:
                self.state.notify(f"could not write {request}: {exc}", "error")

    def _update_title(self) -> None:
        s = self.state.settings
        name = Path(s.scene).name if ("/" in s.scene or "." in s.scene) else s.scene
        self.window.set_title(f"lpv-explorer — {name} — {preset_name(s.corrections)}")



def _recover_stacks(stacks) -> None:
    """Close what a failed panel left open (children, groups, fonts, styles, ids) back to
    ``stacks``, so that the frame still ends cleanly (imgui would assert in its end-of-
    frame checks). The recovery's own reports are off meanwhile: the failure was shown."""
    from imgui_bundle import imgui

    io = imgui.get_io()
    asserts = io.config_error_recovery_enable_assert
    io.config_error_recovery_enable_assert = False
    try:
        imgui.internal.error_recovery_try_to_recover_state(stacks)
    finally:
        io.config_error_recovery_enable_assert = asserts
