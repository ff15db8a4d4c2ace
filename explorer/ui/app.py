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

    app = App(options=WindowOptions(width=800, height=600, visible=False))
    app.state.set_corrections(propagation_4pi=False)
    app.settle()                     # frames until the picture has converged
    app.screenshot("shot.png")       # the whole window, panels included
    app.close()
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

from explorer import stop_signals
from explorer.gl.window import Window
from explorer.lpv.settings import Settings, preset_name
from explorer.ui import animation, frame_pacing, memory, persist, theme
from explorer.ui.figure_cache import FigureCache
from explorer.ui.frame_pacing import FRAMES_AFTER_INPUT, PROGRESS_REDRAW_S
from explorer.ui.frame_profile import FrameProfile
from explorer.ui.images import write_png
from explorer.ui.partial_paint import PartialPainter
from explorer.ui.side_display import ALL_SIDES
from explorer.ui.state import AppState, fit_window_size, release_screenshot_path
from explorer.ui.view_size import LAYOUT_FRAMES, ViewSizeFollower
from explorer.ui.window_options import WindowOptions
from explorer.ui.window_panels import WindowPanels

SETTLE_FRAMES = 100000


class App:
    """One explorer window over one AppState (module docstring)."""

    def __init__(self, state: AppState | None = None,
                 options: WindowOptions | None = None) -> None:
        """A window over ``state`` (default: a new AppState, with the saved settings read
        when ``options.persist_settings``), opened as ``options`` says."""
        options = options or WindowOptions()
        self.options = options
        memory.return_large_blocks()      # resident memory that comes down again
        width, height, visible, headless = (options.width, options.height, options.visible,
                                            options.headless)
        persist_settings, pipeline_class = options.persist_settings, options.pipeline_class
        self.state = state or AppState()
        self.persist_settings = persist_settings
        self.wait_when_idle = options.waits_when_idle
        self.idle_timeout_s = float(options.idle_timeout_s)
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
        self.window = Window(*size, visible=visible and not headless, vsync=options.vsync,
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
            rt.frame.pipeline_error = (
                "no LPV pipeline attached (WindowOptions(pipeline_class=None)): the panels "
                "work, the view stays empty")
        self._view_size = ViewSizeFollower()
        self._capture = False
        self._quiet = False           # the last frame found nothing to do: wait next time
        self._heaps_trimmed = False   # the heaps' free pages went back since the last work
        self.idle_falls = 0
        """Times the window fell idle (and released what only a job in progress uses)."""
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
        """frame() calls that found nothing to do and drew nothing."""
        self.last_wait_s = 0.0
        """How long the last frame() waited for events (an idle window)."""
        self.draw_phases_ms: dict[str, float] = {}
        """The last drawn frame's drawing by phase (:meth:`frame`), in milliseconds."""
        self.profile = FrameProfile()
        """The last drawn frame by phase, the pipelines' update included
        (explorer/ui/frame_profile.py; ``profile.finish = ctx.finish`` to diagnose)."""
        self.last_pixels: np.ndarray | None = None
        self.panels = WindowPanels(self.state)
        """The menu bar, the dock layout and the panels (explorer/ui/window_panels.py)."""
        self._init_imgui(options.test_engine, options.partial_paint)
        self.test_engine = self._imgui.test_engine
        # SIGTERM / SIGHUP: quit as the Quit item does (close() saves); a second: at once
        self._restore_signals = stop_signals.calling(self._quit_on_signal)

    def _quit_on_signal(self, signum: int) -> None:
        self.state.requests.quit = True

    # -- setup ---------------------------------------------------------------------------
    def _init_imgui(self, test_engine: bool = False, partial_paint: bool = True) -> None:
        from imgui_bundle import imgui

        from explorer.ui.formulas import FormulaCache
        from explorer.ui.imgui_host import ImguiHost
        from explorer.ui.overlays.compositor import Compositor
        from explorer.ui.textures import UiTextures

        self._imgui = ImguiHost(self.window, test_engine=test_engine,
                                partial_paint=partial_paint)
        io = imgui.get_io()
        io.config_flags |= imgui.ConfigFlags_.docking_enable
        io.config_flags |= imgui.ConfigFlags_.nav_enable_keyboard
        self.panels.load_layout(self.persist_settings)
        theme.apply_style(self.window.content_scale)
        from explorer.ui import fonts

        self.state.runtime.services.fonts = fonts.load(io, 15.0)   # Roboto + math symbols
        self._imgui.start_backends()
        rt = self.state.runtime
        rt.services.textures = UiTextures(self.ctx)
        rt.services.compositor = Compositor(self.ctx)     # the View panel's in-scene overlays
        # the lesson figures' pictures; with the test engine every figure draws live (the
        # engine finds a figure's widgets only in the frames that draw them)
        rt.services.figure_cache = FigureCache(self.ctx, enabled=not test_engine)
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
            if status is None and self.state.runtime.frame.frame_index > LAYOUT_FRAMES:
                return drawn         # no pipeline (or no GL): nothing to wait for
        return max_frames

    @property
    def painter(self) -> PartialPainter:
        """What paints imgui's lists where they changed (explorer/ui/partial_paint.py)."""
        return self._imgui.painter

    @property
    def fallen_idle(self) -> bool:
        """The window fell idle and had nothing to do since (it released what only a job
        in progress uses and trimmed its heaps)."""
        return self._heaps_trimmed

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
            self.window.poll_events(timeout=self.idle_timeout())
            self.last_wait_s = time.perf_counter() - waited
        start = time.perf_counter()         # the frame's time, without the idle wait
        self.profile.start()
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
        expired = frame_pacing.message_expired(self.state, self._drawn_at)
        must_draw = (force or events or changed or rt.redraw or self._draws_pending
                     or expired or (status is not None and (
                         status.published or status.failures > 0)))
        if not must_draw and not worked:
            if not self._heaps_trimmed:     # fallen idle: what only a job in progress
                # uses, then the heaps' free pages, go back
                memory.release_between_runs(self.controller.sides.values())
                memory.give_back_free()
                self._heaps_trimmed = True
                self.idle_falls += 1
            self._quiet = True              # nothing to do: wait for events next time
            self.frames_skipped += 1
            return True
        self._heaps_trimmed = False
        if not must_draw and time.monotonic() - self._drawn_at < PROGRESS_REDRAW_S:
            # a job runs with nothing new to show: its time goes to the job (input is
            # still read between budgets); the progress label is redrawn this often.
            # The next frame goes on with it, never waiting for events.
            self._quiet = False
            self.frames_skipped += 1
            return True
        rt.ask_again()                      # what is drawn now asks again
        before_draw = self._fingerprint()
        self.profile.mark("update")
        self._imgui.new_frame()
        imguizmo.im_guizmo.begin_frame()
        settings = self.state.settings
        self.panels.draw()
        frame_pacing.note_setting_drag(self.state, settings)
        from explorer.ui import widgets

        rt.redraw = rt.redraw or widgets.animating()
        self.profile.mark("panels")
        self._imgui.render(self.ctx, theme.CLEAR_COLOUR)
        self._after_render(capture)
        self.profile.mark("render")
        self.window.swap_buffers()
        self._imgui.post_swap()
        self.profile.mark("swap")
        # the window's own drawing, apart from the pipeline's work (bench --interactive):
        # the panels built on the CPU, imgui's draw lists rendered (a software renderer
        # rasterises them by the swap, or when a phase finishes: frame_profile.py), the swap
        self.draw_phases_ms = {phase: self.profile.wall_ms[phase]
                               for phase in ("panels", "render", "swap")}
        rt.frame.frame_index += 1
        rt.frame.frame_ms = (time.perf_counter() - start) * 1000.0
        work_ms = status.work_ms if status is not None else 0.0
        # the window's own cost per frame (panels, drawing, swap), smoothed
        self.ui_ms += 0.2 * (max(rt.frame.frame_ms - work_ms, 0.0) - self.ui_ms)
        if status is not None:       # what showing a finished frame draws more (kept free)
            self.controller.result_drawing.note(rt.frame.frame_ms - work_ms + status.snapshot_ms,
                                                status.finished)
        self._draws_pending = FRAMES_AFTER_INPUT if (events or changed) else max(
            self._draws_pending - 1, 0)
        self._seen = self._fingerprint()
        self.drew_change = self._seen != before_draw
        self._drawn_at = time.monotonic()
        self._quiet = frame_pacing.may_wait(worked or rt.redraw or self._draws_pending > 0,
                                            self._interacted, self.interacting())
        return True

    def note_input(self) -> None:
        """Input arrived that the window's events do not show (Dear ImGui Test Engine's
        simulated mouse and keys): the pipelines keep to the frame budget, as for a
        reader's input, instead of the quiet budget of a window nobody touches."""
        self._input_at = time.monotonic()

    def interacting(self) -> bool:
        """The camera, an object or the animation moves (explorer/ui/frame_pacing.py)."""
        return frame_pacing.interacting(self.state)

    def idle_timeout(self) -> float:
        """How long an idle loop may wait now (explorer/ui/frame_pacing.py)."""
        return frame_pacing.idle_timeout(self.state, self.idle_timeout_s)

    def _fingerprint(self) -> tuple:
        return frame_pacing.fingerprint(self.state)

    def screenshot(self, path: str | Path) -> Path:
        """Draw a frame and write it, panels included, to ``path`` (PNG)."""
        self.frame(capture=True)
        path = Path(path)
        write_png(self.last_pixels, path)
        return path

    def close(self) -> None:
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
        for owned in (rt.services.composer, rt.services.textures, rt.services.compositor,
                      rt.services.figure_cache):
            if owned is not None:
                owned.release()
        rt.services.composer = None
        rt.frame.pictures = {}
        self.controller.release()
        if self.persist_settings:
            try:
                self.panels.save_layout()
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
        if not self._view_size.follow(state):
            return
        drag_budget = frame_pacing.drag_budget_ms(self.ui_ms)
        interacted, self._interacted = self._interacted, self.interacting()
        if interacted and not self._interacted:
            # a drag or a camera move has just settled: its full-size frame starts now, and
            # it counts as input (the quiet budget waits as long after it as after a key)
            self._input_at = time.monotonic()
        self.status = self.controller.update(
            state, state.frame_budget_ms,
            need_audit=rt.audit_of_sides(ALL_SIDES), interacting=self._interacted,
            drag_budget_ms=drag_budget, draw_ms=self.ui_ms,
            quiet_s=self._quiet_s(), input_pending=self._input_pending)
        rt.frame.progress = dict(self.status.labels)
        rt.frame.displays = {side: self.controller.side_display(state, side)
                       for side in rt.frame.pictures}
        if rt.frame.result is not None and rt.frame.result is not self._shown_result:
            self._shown_result = rt.frame.result
            self._update_title()

    def _quiet_s(self) -> float:
        """Seconds since the last input (or the end of a camera move), as the controller's
        quiet budget reads them; 0 when this frame will be drawn anyway for the progress
        label (a frame that draws keeps to the frame budget: its work and its drawing stay
        one frame's worth)."""
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

    def _handle_drops(self) -> None:
        dropped = self.window.dropped_paths
        while dropped:
            path = dropped.popleft()
            self.state.mesh_path = str(path)
            self.state.requests.open_scene = str(path)

    def _after_render(self, capture: bool) -> None:
        figures = self.state.runtime.services.figure_cache
        if figures is not None:
            figures.capture(self.window.framebuffer_size)
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
                release_screenshot_path(request)

    def _update_title(self) -> None:
        s = self.state.settings
        name = Path(s.scene).name if ("/" in s.scene or "." in s.scene) else s.scene
        self.window.set_title(f"lpv-explorer — {name} — {preset_name(s.corrections)}")

