"""The window's imgui side: the dock layout (read from and written to the layout file,
rebuilt when the panel set changed), the menu bar, every panel drawn in its dock (a panel
that raises is shown failed, the others draw on), the GL problem window and the file
dialogs."""

from __future__ import annotations

import sys
import time
import traceback
from pathlib import Path

from explorer.lpv.settings import PRESETS
from explorer.ui import persist, theme
from explorer.ui.state import AppState, default_screenshot_path

TAB_PADDING_X = 3.0
"""Horizontal padding of a dock tab's title (the style's frame padding is 6)."""


class WindowPanels:
    """The panels of one window over one AppState, with its layout."""

    def __init__(self, state: AppState) -> None:
        self.state = state
        self.layout_file = persist.layout_path()
        self.layout_loaded = False
        self.needs_layout = True
        """The default dock layout is built on the next frame."""
        self.docked: dict[str, bool] = {}
        """Panel title -> whether it was docked when last drawn (its background: draw)."""
        self.panel_errors: list[str] = []
        """Every panel failure so far (an exception its gui function raised)."""
        self.panel_ms: dict[str, float] = {}
        """Panel title -> milliseconds its gui function took when last drawn (the
        window bench names the slowest panel of a slow frame)."""

    def load_layout(self, persist_settings: bool) -> None:
        """Read the saved layout (imgui never opens the layout file itself: it would block
        on a FIFO and write in place; persist.py reads it safely and writes atomically),
        and build the default one on the first run or when the panel set changed (a panel
        the saved layout does not know would otherwise float on its own)."""
        from imgui_bundle import imgui

        from explorer.ui.layout import PANELS

        imgui.get_io().set_ini_filename("")
        if persist_settings:
            # imgui asserts on a layout it cannot use: checked first, set aside if bad
            layout, problem = persist.load_layout(self.layout_file)
            if problem:
                print(f"lpv-explorer: {problem}", file=sys.stderr)
                self.state.notify(problem, "warning")
            if layout:
                imgui.load_ini_settings_from_memory(layout)
                self.layout_loaded = True
        titles = [panel.title for panel in PANELS]
        self.needs_layout = not (self.layout_loaded
                                 and sorted(self.state.layout_panels) == sorted(titles))
        self.state.layout_panels = titles

    def save_layout(self) -> None:
        """Write the dock layout to the layout file (atomically)."""
        from imgui_bundle import imgui

        persist.save_layout(imgui.save_ini_settings_to_memory(), self.layout_file)

    # complexity: the window's panels in the order they are drawn
    def draw(self) -> None:  # noqa: C901
        """The menu bar, the dock space and every open panel (one frame's imgui calls)."""
        from imgui_bundle import imgui

        from explorer.ui.layout import PANELS, build_default_layout, window_class

        state = self.state
        self.panel_ms = {}
        self._main_menu()
        viewport = imgui.get_main_viewport()
        dock_id = imgui.get_id("lpv-dockspace")
        size = viewport.work_size
        # a window not yet sized (some glfw and imgui-bundle versions report 0 for the first
        # frame) builds its layout on the next frame: the dock builder asserts on size 0
        if (self.needs_layout or state.requests.reset_layout) and size.x > 0 and size.y > 0:
            build_default_layout(dock_id, size)
            self.needs_layout = False
            state.requests.reset_layout = False
        # the dock nodes' tabs are laid out here: narrower padding keeps three titles
        # whole in the tool column at 1280 px (imgui cuts tabs that do not fit)
        imgui.push_style_var(imgui.StyleVar_.frame_padding,
                             (TAB_PADDING_X, imgui.get_style().frame_padding.y))
        # the dock space's host window covers the whole window: its background, the
        # clear's colour again, would be one more full-window layer of fill (1.5 Mpx at
        # 1600×960, two thirds of a redraw's rasterising on llvmpipe); transparent, imgui
        # draws none
        imgui.push_style_color(imgui.Col_.window_bg, theme.DOCKED_WINDOW_BG)
        imgui.dock_space_over_viewport(dock_id, viewport)
        imgui.pop_style_color()
        imgui.pop_style_var()
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
            if panel.title in focus and not self.needs_layout:
                state.open_panels[panel.title] = True
            if not state.open_panels.get(panel.title, True) or panel.title in hidden:
                continue
            if focus and panel.title == focus[0] and not self.needs_layout:
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
            docked = self.docked.get(panel.title, False)
            if docked:
                imgui.push_style_color(imgui.Col_.window_bg, theme.DOCKED_WINDOW_BG)
            expanded, still_open = imgui.begin(panel.title, True)
            if docked:
                imgui.pop_style_color()
            self.docked[panel.title] = imgui.is_window_docked()
            if not panel.padding:
                imgui.pop_style_var()
            if expanded:
                stacks = imgui.internal.ErrorRecoveryState()
                imgui.internal.error_recovery_store_state(stacks)
                began = time.perf_counter()
                try:
                    panel.gui(state)
                except Exception as exc:  # noqa: BLE001 - one broken panel, not the app
                    self._panel_failed(panel.title, exc)
                    _recover_stacks(stacks)
                self.panel_ms[panel.title] = (time.perf_counter() - began) * 1e3
            imgui.end()
            state.open_panels[panel.title] = bool(still_open)
        if focus and not self.needs_layout and state.requests.focus_panel is requested:
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

    # complexity: one branch per menu item, in the menu's order
    def _main_menu(self) -> None:  # noqa: C901
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
            from explorer.lessons.words import for_reader
            from explorer.ui.widgets import LEVEL_COLOURS

            last = state.messages[-1]
            if time.monotonic() - last.created < 20.0 or last.level == "error":
                said = for_reader(last.text)      # no file or function cited at the reader
                text = said if len(said) < 110 else said[:107] + "…"
                imgui.same_line(max(imgui.get_window_width() - imgui.calc_text_size(text).x
                                    - 16, 300))
                imgui.text_colored(LEVEL_COLOURS.get(last.level), text)
                if text != said and imgui.is_item_hovered():
                    imgui.set_tooltip(said)       # the whole message
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
