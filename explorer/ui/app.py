"""The explorer window: one glfw window, imgui panels over one AppState, two pipelines.

The app is a thin shell over the headless :class:`explorer.lpv.pipeline.Pipeline`: each
frame it hands the current Settings to the pipeline (which re-runs only when the Settings
differ from the last run's), shows ``Pipeline.final_texture`` in the View panel and lets
the panels read the FrameResult. Configuration B (compare views) is a second Pipeline with
its own Settings that differ from A's only in the corrections (and, optionally, exposure).

Drive it from code (tests, scripts)::

    app = App(width=800, height=600, visible=False)
    app.state.set_corrections(propagation_4pi=False)
    app.frame()                      # the change is visible in this frame
    app.screenshot("shot.png")       # the whole window, panels included
    app.close()
"""

from __future__ import annotations

import sys
import time
import traceback
from pathlib import Path
from typing import Callable

import numpy as np

from explorer.gl.window import Window
from explorer.lpv.settings import PRESETS, Settings, preset_name
from explorer.ui import animation, persist, theme
from explorer.ui.images import write_png
from explorer.ui.state import AppState, default_screenshot_path, fit_window_size

_MIN_RENDER_SIZE = 16
_MAX_RENDER_SIZE = 2048
_RESIZE_SETTLE_S = 0.15       # re-render at a new view size once resizing pauses this long
_SHADER_POLL_S = 0.5
_LAYOUT_FRAMES = 2          # frames before the View panel's size is trusted
_EXPOSURE_TOLERANCE = 0.05    # relative change of auto-exposure worth a re-run
_TASK_BUDGET_S = 0.06         # background GPU work per frame (the Error panel's reference)


class App:
    def __init__(self, state: AppState | None = None, *, width: int | None = None,
                 height: int | None = None,
                 visible: bool = True, vsync: bool = True, persist_settings: bool = True,
                 pipeline_class: Callable | None | object = ...) -> None:
        """``pipeline_class``: the Pipeline class (default: explorer.lpv.pipeline's), or
        None for a window without a pipeline (panels only: the window tests)."""
        self.state = state or AppState()
        self.persist_settings = persist_settings
        if persist_settings and state is None:
            problem = persist.load_state(self.state)
            if problem:
                print(f"lpv-explorer: {problem}", file=sys.stderr)
                self.state.notify(problem, "warning")
        # The window opens at the given size, else at the size it had when it was closed.
        saved_w, saved_h = self.state.window_size
        self.window = Window(width or saved_w, height or saved_h, visible=visible, vsync=vsync)
        self.ctx = self.window.ctx
        rt = self.state.runtime
        rt.gl_problem = self.window.gl_problem
        rt.gl_renderer = str(self.ctx.info.get("GL_RENDERER", "")) if self.ctx else ""
        if rt.gl_problem:
            print(f"lpv-explorer: {rt.gl_problem}", file=sys.stderr)
        if pipeline_class is ...:
            from explorer.lpv.pipeline import Pipeline as pipeline_class
        self._pipeline_class = pipeline_class
        if pipeline_class is None and not rt.gl_problem:
            rt.pipeline_error = ("no LPV pipeline attached (App(pipeline_class=None)): the "
                                 "panels work, the view stays empty")
        self._pipelines: dict[str, object] = {}
        self._last_run: dict[str, object] = {}
        self._failed: dict[str, object] = {}
        self._warned: dict[str, tuple[str, ...]] = {}   # side -> warnings of its last result
        self._ran_settings: Settings | None = None   # state.settings when A last ran
        self._good_scene: tuple | None = None
        self._defaults_for: str | None = None
        self._exposure_seen: list = [None, None]
        self._pending_size: tuple | None = None
        self._shader_poll = 0.0
        self._capture = False
        self.last_pixels: np.ndarray | None = None
        self._init_imgui()

    # -- setup ---------------------------------------------------------------------------
    def _init_imgui(self) -> None:
        from imgui_bundle import imgui, implot, implot3d

        from explorer.ui.formulas import FormulaCache
        from explorer.ui.overlays.compositor import Compositor
        from explorer.ui.textures import UiTextures

        self._imgui_ctx = imgui.create_context()
        self._implot_ctx = implot.create_context()
        self._implot3d_ctx = implot3d.create_context()
        io = imgui.get_io()
        io.config_flags |= imgui.ConfigFlags_.docking_enable
        io.config_flags |= imgui.ConfigFlags_.nav_enable_keyboard
        self._layout_file = persist.layout_path()
        if self.persist_settings:
            self._layout_file.parent.mkdir(parents=True, exist_ok=True)
            # imgui asserts on a layout it cannot use: check it first, set it aside if bad
            problem = persist.check_layout_file(self._layout_file)
            if problem:
                print(f"lpv-explorer: {problem}", file=sys.stderr)
                self.state.notify(problem, "warning")
            io.set_ini_filename(str(self._layout_file))
        else:
            io.set_ini_filename("")
        from explorer.ui.layout import PANELS

        titles = [panel.title for panel in PANELS]
        # Rebuild the default layout on the first run and whenever the panel set changed
        # (a panel the saved layout does not know would otherwise float on its own).
        self._needs_layout = not (self.persist_settings and self._layout_file.exists()
                                  and sorted(self.state.layout_panels) == sorted(titles))
        self.state.layout_panels = titles
        theme.apply_style(self.window.content_scale)
        from explorer.ui import fonts

        self.state.runtime.fonts = fonts.load(io, 15.0)   # Roboto + math symbols
        imgui.backends.glfw_init_for_opengl(self.window.address, True)
        imgui.backends.opengl3_init("#version 330 core")
        rt = self.state.runtime
        rt.textures = UiTextures(self.ctx)
        rt.compositor = Compositor(self.ctx)     # the View panel's in-scene overlays
        rt.formulas = FormulaCache(rt.textures, font_size=17.0 * self.window.content_scale)
        self._markdown_ctx = theme.markdown_context()
        rt.markdown_ready = self._markdown_ctx is not None
        try:
            from imgui_bundle import portable_file_dialogs as pfd

            rt.file_dialog_available = bool(pfd.settings.available())
        except Exception:  # noqa: BLE001 - no zenity/kdialog: hide the browse button
            rt.file_dialog_available = False

    # -- the loop ------------------------------------------------------------------------
    def run(self, frames: int | None = None, screenshot: Path | None = None) -> int:
        """Run until the window closes (or for ``frames`` frames, then write
        ``screenshot`` if given). Returns an exit status."""
        count = 0
        while self.frame(capture=screenshot is not None and frames is not None
                         and count == frames - 1):
            count += 1
            if frames is not None and count >= frames:
                break
        if screenshot is not None:
            if self.last_pixels is None:
                print("lpv-explorer: no frame was drawn, no screenshot written",
                      file=sys.stderr)
                return 1
            write_png(self.last_pixels, screenshot)
            print(f"lpv-explorer: wrote {screenshot}")
        return 0

    def frame(self, capture: bool = False) -> bool:
        """Process events and draw one frame; False once the window should close.

        ``capture``: keep the drawn frame (panels included) in :attr:`last_pixels`."""
        from imgui_bundle import imgui, imguizmo

        start = time.perf_counter()
        self.window.poll_events()
        if self.window.should_close() or self.state.requests.quit:
            return False
        self._handle_drops()
        if self.window.minimised:
            # Nothing to draw into: skip GL work entirely and sleep until an event.
            self.window.poll_events(timeout=0.1)
            return True
        if not self.state.runtime.gl_problem:
            self._hot_reload()
            animation.tick(self.state)       # playing paths and fly-through: new Settings
            self._update_pipelines()
            self._background_tasks()
        imgui.backends.opengl3_new_frame()
        imgui.backends.glfw_new_frame()
        imgui.new_frame()
        imguizmo.im_guizmo.begin_frame()
        self._draw_ui()
        imgui.render()
        width, height = self.window.framebuffer_size
        self.ctx.screen.use()
        self.ctx.viewport = (0, 0, width, height)
        self.ctx.clear(*theme.CLEAR_COLOUR)
        imgui.backends.opengl3_render_draw_data(imgui.get_draw_data())
        self._after_render(capture)
        self.window.swap_buffers()
        rt = self.state.runtime
        rt.frame_index += 1
        rt.frame_ms = (time.perf_counter() - start) * 1000.0
        return True

    def screenshot(self, path: str | Path) -> Path:
        """Draw a frame and write it, panels included, to ``path`` (PNG)."""
        self.frame(capture=True)
        path = Path(path)
        write_png(self.last_pixels, path)
        return path

    def close(self) -> None:
        from imgui_bundle import imgui, implot, implot3d

        if self.persist_settings:
            try:
                if not self.window.minimised:
                    self.state.window_size = fit_window_size(self.window.size)
                self._keep_settings_that_ran()
                persist.save_state(self.state)
            except OSError as exc:
                print(f"lpv-explorer: could not save settings: {exc}", file=sys.stderr)
        for pipeline in self._pipelines.values():
            pipeline.release()
        self._pipelines.clear()
        rt = self.state.runtime
        for task in rt.tasks:
            task.release()
        rt.tasks.clear()
        if rt.textures is not None:
            rt.textures.release()
        if rt.compositor is not None:
            rt.compositor.release()
        if self.persist_settings:
            imgui.save_ini_settings_to_disk(str(self._layout_file))
        if self._markdown_ctx is not None:
            from imgui_bundle import rich_md

            rich_md.destroy_context(self._markdown_ctx)
            self._markdown_ctx = None
        imgui.backends.opengl3_shutdown()
        imgui.backends.glfw_shutdown()
        implot3d.destroy_context(self._implot3d_ctx)
        implot.destroy_context(self._implot_ctx)
        imgui.destroy_context(self._imgui_ctx)
        self.window.close()

    def _keep_settings_that_ran(self) -> None:
        """Before saving: settings the pipeline refused are not written back; the last
        settings that ran take their place (the defaults when none ran)."""
        failed = self._failed.get("A")
        if failed is not None and failed[0] == self.settings_for("A"):
            self.state.settings = self._ran_settings or Settings()

    # -- pipelines -----------------------------------------------------------------------
    def settings_for(self, side: str):
        """The Settings the pipeline of ``side`` ("A" or "B") runs with this frame."""
        state, rt = self.state, self.state.runtime
        a = state.settings
        # With the display's auto exposure (Settings.auto_exposure) each side already has
        # its own display scale; expose_sides_separately then only decides whether B keeps
        # it (_display_override). Without it, it sets each side's exposure.
        per_side_exposure = state.expose_sides_separately and not a.auto_exposure
        if side == "A":
            if state.comparing and per_side_exposure:
                a = a.with_changes(exposure=rt.side_exposures[0])
            return a
        b = a.with_changes(corrections=state.compare_settings.corrections,
                           **dict(state.compare_overrides))
        if per_side_exposure:
            b = b.with_changes(exposure=rt.side_exposures[1])
        return b

    def _display_override(self, side: str) -> float | None:
        """The display scale side B is shown with: A's, so that the two sides of a
        comparison are exposed alike (unless "Expose sides separately" is on); None (its
        own) for A and for B exposed on its own."""
        rt = self.state.runtime
        if side == "A" or self.state.expose_sides_separately or rt.result is None:
            return None
        return float(rt.result.display_scale)

    def _follow_view_size(self) -> bool:
        """Keep the render size at the View panel's pixels; False while the size is
        not known yet (the first frame), so the first run already has the right size."""
        state, rt = self.state, self.state.runtime
        if not state.follow_view_size:
            return True
        vw, vh = rt.view_size
        if rt.frame_index < _LAYOUT_FRAMES:
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
        if rt.result is None or (self._pending_size and self._pending_size[0] == size
                                 and now - self._pending_size[1] >= _RESIZE_SETTLE_S):
            state.update(width=size[0], height=size[1])
            self._pending_size = None
        elif not self._pending_size or self._pending_size[0] != size:
            self._pending_size = (size, now)
        return True

    def _update_pipelines(self) -> None:
        rt = self.state.runtime
        if self._pipeline_class is None:
            return
        if self.state.requests.open_scene:
            self._open_scene(self.state.requests.open_scene)
            self.state.requests.open_scene = None
        if not self._follow_view_size():
            return
        keep_steps = (self.state.inspect.source == "propagation"
                      or self.state.overlays.needs_steps)
        if self._run_side("A", keep_steps):
            rt.final_texture_id = self._pipelines["A"].final_texture.glo
        if self.state.comparing:
            if self._run_side("B", self.state.overlays.needs_steps):
                rt.compare_texture_id = self._pipelines["B"].final_texture.glo
        self._update_side_exposures()

    def _run_side(self, side: str, keep_steps: bool) -> bool:
        """Run one side's pipeline if its settings changed; True if it has a result."""
        rt = self.state.runtime
        settings = self.settings_for(side)
        override = self._display_override(side)
        existing = self._pipelines.get(side)
        if existing is not None and getattr(existing, "display_scale_override", None) != override:
            existing.display_scale_override = override
            self._last_run.pop(side, None)   # the pipeline re-runs only its display stage
        last = self._last_run.get(side)
        if last is not None and last == (settings, keep_steps):
            return True
        if self._failed.get(side) == (settings, keep_steps):
            return side in self._last_run
        start = time.perf_counter()
        try:
            pipeline = self._pipelines.get(side)
            if pipeline is None:
                pipeline = self._pipeline_class(settings, ctx=self.ctx)
                pipeline.display_scale_override = override
                self._pipelines[side] = pipeline
            result = pipeline.run(settings, keep_steps=keep_steps)
        except Exception as exc:  # noqa: BLE001 - shown in the window, the app goes on
            self._failed[side] = (settings, keep_steps)
            self._pipeline_failed(side, settings, exc)
            return side in self._last_run
        finally:
            self.ctx.screen.use()
        rt.pipeline_ms = (time.perf_counter() - start) * 1000.0
        self._last_run[side] = (settings, keep_steps)
        self._failed.pop(side, None)
        self._post_warnings(side, result)
        if side == "A":
            rt.result = result
            rt.frame_view = getattr(pipeline, "view", None)
            rt.pipeline_error = None
            self._ran_settings = self.state.settings
            self._good_scene = (settings.scene, settings.camera, settings.light,
                                settings.light_flux)
            self._scene_defaults(pipeline, settings.scene)
            self._update_title()
        else:
            rt.compare_result = result
        return True

    def _background_tasks(self) -> None:
        """Advance the panels' background GPU work (``runtime.tasks``) within a small
        time budget, so that the window keeps drawing while it runs."""
        for task in list(self.state.runtime.tasks):
            try:
                task.advance(self.ctx, _TASK_BUDGET_S)
            except Exception as exc:  # noqa: BLE001 - shown in the window, the app goes on
                self.state.notify(f"{type(task).__name__} failed: {exc}", "error")
                traceback.print_exception(exc, file=sys.stderr)
                task.release()
                self.state.runtime.tasks.remove(task)
            finally:
                self.ctx.screen.use()

    def _post_warnings(self, side: str, result) -> None:
        """The numeric guards' warnings of a new result (``FrameResult.warnings``) in the
        Messages panel: each one the side's previous result did not have, once."""
        warnings = tuple(getattr(result, "warnings", ()) or ())
        before = self._warned.get(side, ())
        for text in warnings:
            if text not in before:
                self.state.notify(text if side == "A" else f"B: {text}", "warning")
        self._warned[side] = warnings

    def _pipeline_failed(self, side: str, settings, exc: Exception) -> None:
        rt = self.state.runtime
        text = f"{type(exc).__name__}: {exc}"
        if self._good_scene is None and settings.scene != Settings().scene and side == "A":
            # The scene saved last time (a mesh since moved, say) cannot open: start from
            # the default scene rather than an empty view.
            self._good_scene = (Settings().scene, None, None, None)
        scene_error = self._good_scene is not None and settings.scene != self._good_scene[0]
        if scene_error and side == "A":
            # A mesh that fails to load: say so and keep the previous scene.
            scene, camera, light, flux = self._good_scene
            self.state.notify(f"could not open {settings.scene}: {exc}", "error")
            self.state.update(scene=scene, camera=camera, light=light, light_flux=flux)
            print(f"lpv-explorer: could not open {settings.scene}: {exc}", file=sys.stderr)
            return
        rt.pipeline_error = f"pipeline {side} failed: {text}"
        self.state.notify(rt.pipeline_error, "error")
        print(f"lpv-explorer: {rt.pipeline_error}", file=sys.stderr)
        traceback.print_exception(exc, file=sys.stderr)

    def _scene_defaults(self, pipeline, scene_name: str) -> None:
        """The scene's own camera and light (before any override), so orbiting and the
        light sliders start from what is shown. Loaded once per scene."""
        rt = self.state.runtime
        if self._defaults_for == scene_name:
            return
        self._defaults_for = scene_name
        scene = getattr(pipeline, "base_scene", None)
        if scene is None:
            try:
                from explorer.scene import load_scene

                scene = load_scene(scene_name)
            except Exception:  # noqa: BLE001 - defaults are a convenience
                scene = None
        rt.scene = None if scene is None else (scene_name, scene)
        rt.camera_default = _eye_target(getattr(scene, "camera", None))
        try:     # the primary light of the lights that shine (Settings.lights)
            light = scene.with_lights(self.state.settings.lights).light
        except Exception:  # noqa: BLE001 - no scene, or lights it does not have
            light = getattr(scene, "light", None)
        rt.light_default = _eye_target(light)
        rt.light_flux_default = getattr(light, "flux", None)
        rt.light_cone_default = getattr(light, "cone_degrees", None)
        rt.light_is_spot = hasattr(light, "cone_degrees")

    def _open_scene(self, name_or_path: str) -> None:
        if name_or_path == self.state.settings.scene:
            return
        # A new scene starts from its own camera, lights and objects.
        self.state.update(scene=str(name_or_path), camera=None, light=None, light_flux=None,
                          lights=None, object_transforms=())
        self.state.notify(f"opening {name_or_path}")

    def _update_side_exposures(self) -> None:
        """Per-side exposure from the latest results (computed once per new result)."""
        from explorer.ui.images import auto_exposure

        rt = self.state.runtime
        if not (self.state.comparing and self.state.expose_sides_separately) or \
                self.state.settings.auto_exposure:
            return
        values = list(rt.side_exposures)
        for i, result in enumerate((rt.result, rt.compare_result)):
            if result is None or self._exposure_seen[i] == id(result):
                continue
            self._exposure_seen[i] = id(result)
            value = auto_exposure(result.final_image, result.settings.exposure)
            if abs(value - values[i]) > _EXPOSURE_TOLERANCE * max(values[i], 1e-12):
                values[i] = float(f"{value:.3g}")
        rt.side_exposures = (values[0], values[1])

    def _hot_reload(self) -> None:
        """Recompile shaders whose files changed: each pipeline's ProgramCache reloads in
        place (a failed compile keeps the last good program and records its log)."""
        now = time.monotonic()
        if now - self._shader_poll < _SHADER_POLL_S or not self._pipelines:
            return
        self._shader_poll = now
        rt = self.state.runtime
        for side, pipeline in list(self._pipelines.items()):
            if pipeline.reload_shaders():
                self._last_run.pop(side, None)
                self.state.notify(f"shaders reloaded ({side})")
            rt.shader_errors = dict(pipeline.programs.errors)

    # -- UI ------------------------------------------------------------------------------
    def _draw_ui(self) -> None:
        from imgui_bundle import imgui

        from explorer.ui.layout import PANELS, build_default_layout, window_class

        state = self.state
        self._main_menu()
        viewport = imgui.get_main_viewport()
        dock_id = imgui.get_id("lpv-dockspace")
        if self._needs_layout or state.requests.reset_layout:
            build_default_layout(dock_id, viewport.work_size)
            self._needs_layout = False
            state.requests.reset_layout = False
        imgui.dock_space_over_viewport(dock_id, viewport)
        if state.runtime.gl_problem:
            self._gl_problem_window()
            return
        focus = state.requests.focus_panel
        focus = (focus,) if isinstance(focus, str) else tuple(focus or ())
        for panel in PANELS:
            if panel.title in focus and not self._needs_layout:
                state.open_panels[panel.title] = True
            if not state.open_panels.get(panel.title, True):
                continue
            if panel.title in focus and not self._needs_layout:
                imgui.set_next_window_focus()
            if panel.window_class:
                imgui.set_next_window_class(window_class(panel))
            if not panel.padding:
                imgui.push_style_var(imgui.StyleVar_.window_padding, (2.0, 2.0))
            expanded, still_open = imgui.begin(panel.title, True)
            if not panel.padding:
                imgui.pop_style_var()
            if expanded:
                try:
                    panel.gui(state)
                except Exception as exc:  # noqa: BLE001 - one broken panel, not the app
                    self._panel_failed(panel.title, exc)
            imgui.end()
            state.open_panels[panel.title] = bool(still_open)
        if focus and not self._needs_layout:
            state.requests.focus_panel = None
        if imgui.is_key_pressed(imgui.Key.f12, False):
            state.requests.screenshot = default_screenshot_path()
        self._file_dialog()

    def _panel_failed(self, title: str, exc: Exception) -> None:
        text = f"panel {title}: {type(exc).__name__}: {exc}"
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
                    state.runtime.file_dialog_available)):
                state.requests.open_file_dialog = True
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
        imgui.text_wrapped(self.state.runtime.gl_problem or "")
        imgui.text_wrapped("Run `lpv-explorer doctor` for details.")
        if imgui.button("Quit"):
            self.state.requests.quit = True
        imgui.end()

    def _file_dialog(self) -> None:
        state, rt = self.state, self.state.runtime
        if state.requests.open_file_dialog:
            state.requests.open_file_dialog = False
            if rt.file_dialog_available and rt.file_dialog is None:
                from imgui_bundle import portable_file_dialogs as pfd

                rt.file_dialog = pfd.open_file(
                    "Open a mesh", str(Path.home()),
                    ["Meshes", "*.obj *.ply *.stl *.glb *.gltf *.off", "All files", "*"])
        if rt.file_dialog is not None and rt.file_dialog.ready(0):
            chosen = rt.file_dialog.result()
            rt.file_dialog = None
            if chosen:
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




def _eye_target(value) -> tuple | None:
    """(eye, target) from a camera/light object or pair, or None."""
    if value is None:
        return None
    for eye_name, target_name in (("eye", "target"), ("position", "target")):
        if hasattr(value, eye_name) and hasattr(value, target_name):
            eye, target = getattr(value, eye_name), getattr(value, target_name)
            if callable(eye):   # DirectionalLight.eye(bounds) is a method: use position
                continue
            return (tuple(float(v) for v in eye), tuple(float(v) for v in target))
    try:
        eye, target = value
        return (tuple(float(v) for v in eye), tuple(float(v) for v in target))
    except (TypeError, ValueError):
        return None
