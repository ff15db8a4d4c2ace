"""Wireframes in the scene (grid lattice, cascade extents, the picked cell): named sets of
coloured line segments, one draw each."""

from __future__ import annotations

import moderngl
import numpy as np

from explorer.gl.program import ProgramCache, set_uniforms
from explorer.scene.transforms import gl_matrix

PROGRAM = "overlay_lines.glsl"


class LineRenderer:
    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self._sets: dict[str, tuple[moderngl.Buffer, int]] = {}
        self._arrays: dict[str, moderngl.VertexArray] = {}

    def upload(self, name: str, segments: np.ndarray, colours: np.ndarray) -> None:
        """``segments`` (K, 2, 3) world points, ``colours`` (K, 4) RGBA per segment."""
        self.discard(name)
        segments = np.asarray(segments, np.float32).reshape(-1, 2, 3)
        if not len(segments):
            return
        colours = np.repeat(np.asarray(colours, np.float32).reshape(-1, 1, 4), 2, axis=1)
        rows = np.concatenate([segments, colours], axis=2).reshape(-1, 7)
        self._sets[name] = (self.ctx.buffer(np.ascontiguousarray(rows).tobytes()), len(rows))

    def draw(self, target: moderngl.Framebuffer, view_projection: np.ndarray, name: str,
             on_top: bool = False) -> None:
        if name not in self._sets:
            return
        program = self.programs.get(PROGRAM)
        buffer, vertices = self._sets[name]
        array = self._arrays.get(name)
        if array is None or array.program is not program:
            if array is not None:
                array.release()
            array = self.ctx.vertex_array(program, [(buffer, "3f 4f", "in_position",
                                                     "in_colour")])
            self._arrays[name] = array
        set_uniforms(program, {"u_view_projection": gl_matrix(view_projection)})
        flags = moderngl.BLEND | (moderngl.NOTHING if on_top else moderngl.DEPTH_TEST)
        with self.ctx.scope(target, enable_only=flags):
            self.ctx.blend_func = moderngl.DEFAULT_BLENDING
            array.render(moderngl.LINES, vertices=vertices)

    def discard(self, name: str) -> None:
        if name in self._arrays:
            self._arrays.pop(name).release()
        if name in self._sets:
            self._sets.pop(name)[0].release()

    def release(self) -> None:
        for name in list(self._sets):
            self.discard(name)
