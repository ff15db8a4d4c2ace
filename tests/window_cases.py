"""Whether a glfw window can open here (the window tests skip, saying why, when not)."""

from __future__ import annotations


def display_problem() -> str | None:
    try:
        import imgui_bundle  # noqa: F401
        import glfw
    except ImportError as exc:  # pragma: no cover
        return f"glfw/imgui_bundle missing: {exc}"
    if not glfw.init():
        return "no X server could be started (install Xvfb, or pytest-xvfb's xvfb)"
    glfw.terminate()
    return None
