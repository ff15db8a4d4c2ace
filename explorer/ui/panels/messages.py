"""Messages and shader panels: what went wrong (or right), newest first, and the compiler
log of any shader whose hot reload failed (the last good program keeps running)."""

from __future__ import annotations

from imgui_bundle import imgui

from explorer.ui import widgets
from explorer.ui.state import AppState


def gui_messages(state: AppState) -> None:
    if imgui.button("Clear"):
        state.messages.clear()
    rt = state.runtime
    imgui.same_line()
    imgui.text_disabled(f"frame {rt.frame.frame_ms:.1f} ms   "
                        f"last pipeline run {rt.frame.pipeline_ms:.1f} ms")
    if rt.services.gl_problem:
        imgui.text_colored(widgets.ERROR, rt.services.gl_problem)
    if rt.frame.pipeline_error:
        imgui.text_colored(widgets.ERROR, rt.frame.pipeline_error)
    for message in reversed(state.messages):
        imgui.push_style_color(imgui.Col_.text, widgets.LEVEL_COLOURS.get(message.level,
                                                                           widgets.DIM))
        imgui.text_wrapped(message.text)
        imgui.pop_style_color()


def gui_shaders(state: AppState) -> None:
    errors = state.runtime.services.shader_errors
    widgets.dim_text_wrapped(
        "Shaders under shaders/ reload when a file changes. A compile error keeps the last "
        "good program running and shows the log here.")
    if not errors:
        imgui.text_colored(widgets.GOOD, "all shaders compiled")
        return
    for name, log in errors.items():
        imgui.text_colored(widgets.ERROR, name)
        imgui.input_text_multiline(f"##{name}", log, (-1, 120), imgui.InputTextFlags_.read_only)
