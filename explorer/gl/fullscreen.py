"""Drawing the full-screen triangle of ``shaders/fullscreen.glsl`` (downsample, gather)."""

from __future__ import annotations

import moderngl


class FullscreenTriangle:
    """One triangle covering the viewport, drawn with no vertex buffer: the vertex stage
    makes the corners from ``gl_VertexID``. The empty vertex array is bound to a program,
    so it is made again when a hot reload of the shader replaced the program."""

    def __init__(self, ctx: moderngl.Context) -> None:
        self.ctx = ctx
        self._vertex_array: moderngl.VertexArray | None = None

    def draw(self, program: moderngl.Program) -> None:
        """Draw into the bound framebuffer with ``program`` (uniforms already set)."""
        if self._vertex_array is None or self._vertex_array.program is not program:
            self.release()
            self._vertex_array = self.ctx.vertex_array(program, [])
        self._vertex_array.render(moderngl.TRIANGLES, vertices=3)

    def release(self) -> None:
        if self._vertex_array is not None:
            self._vertex_array.release()
            self._vertex_array = None
