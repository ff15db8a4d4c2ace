"""imgui with implot and implot3d on a glfw window's OpenGL context: the contexts, the
backends, one frame's begin and end, and the shutdown. The explorer's window
(:mod:`explorer.ui.app`) and the one-figure window (:mod:`explorer.ui.figures.harness`)
both draw through it, so they set imgui up and tear it down the same way."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import moderngl

    from explorer.gl.window import Window


class ImguiHost:
    """Creates the three contexts (imgui, implot, implot3d); :meth:`start_backends` binds
    them to ``window`` once the caller has configured io, style and fonts.

    ``test_engine``: also start Dear ImGui Test Engine on the imgui context (the click
    tests, :mod:`explorer.ui.test_engine`): :attr:`test_engine` then queues tests, and
    each frame begins and ends through it."""

    def __init__(self, window: Window, test_engine: bool = False,
                 partial_paint: bool = True) -> None:
        from imgui_bundle import imgui, implot, implot3d

        from explorer.ui.partial_paint import PartialPainter

        self.window = window
        self.painter = PartialPainter(window, enabled=partial_paint)
        """Paints imgui's lists where they changed (``partial_paint`` False: whole)."""
        self._imgui_ctx = imgui.create_context()
        self._implot_ctx = implot.create_context()
        self._implot3d_ctx = implot3d.create_context()
        self.test_engine = None
        if test_engine:
            from explorer.ui.test_engine import TestEngine

            self.test_engine = TestEngine(self._imgui_ctx)

    def start_backends(self) -> None:
        """The glfw and OpenGL 3 backends (after io, style and fonts are set)."""
        from imgui_bundle import imgui

        imgui.backends.glfw_init_for_opengl(self.window.address, True)
        imgui.backends.opengl3_init("#version 330 core")

    def new_frame(self) -> None:
        from imgui_bundle import imgui

        imgui.backends.opengl3_new_frame()
        imgui.backends.glfw_new_frame()
        if self.test_engine is not None:
            self.test_engine.new_frame()      # lets a queued test run (its thread)
        else:
            imgui.new_frame()

    def render(self, ctx: moderngl.Context, clear_colour: tuple[float, ...]) -> None:
        """End the frame: paint imgui's draw data over the clear colour into the default
        framebuffer, where it changed (explorer/ui/partial_paint.py); the back buffer holds
        the whole frame afterwards (the caller reads pixels and swaps buffers)."""
        from imgui_bundle import imgui

        if self.test_engine is not None:
            self.test_engine.render()
        else:
            imgui.render()
        self.painter.paint(ctx, imgui.get_draw_data(), clear_colour)

    def post_swap(self) -> None:
        """After the window's buffers were swapped (the test engine counts frames)."""
        if self.test_engine is not None:
            self.test_engine.post_swap()

    def shutdown(self) -> None:
        """The backends, then the contexts in the reverse order of their creation (the
        test engine stops before the imgui context goes and is freed after it)."""
        from imgui_bundle import imgui, implot, implot3d

        if self.test_engine is not None:
            self.test_engine.stop()
        self.painter.release()
        imgui.backends.opengl3_shutdown()
        imgui.backends.glfw_shutdown()
        implot3d.destroy_context(self._implot3d_ctx)
        implot.destroy_context(self._implot_ctx)
        imgui.destroy_context(self._imgui_ctx)
        if self.test_engine is not None:
            self.test_engine.destroy()
            self.test_engine = None
