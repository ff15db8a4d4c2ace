"""Wireframes in the scene (grid lattice, cascade extents, the picked cell): named sets of
coloured line segments, one draw each."""

from __future__ import annotations

import moderngl
import numpy as np

from explorer.gl.program import ProgramCache, set_uniforms
from explorer.gl.targets import scoped
from explorer.scene.transforms import gl_matrix
from explorer.ui.overlays.instanced import BufferSets

PROGRAM = "overlay_lines.glsl"


class LineRenderer:
    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self._sets = BufferSets(ctx)

    def upload(self, name: str, segments: np.ndarray, colours: np.ndarray) -> None:
        """``segments`` (K, 2, 3) world points, ``colours`` (K, 4) RGBA per segment."""
        segments = np.asarray(segments, np.float32).reshape(-1, 2, 3)
        colours = np.repeat(np.asarray(colours, np.float32).reshape(-1, 1, 4), 2, axis=1)
        self._sets.put(name, np.concatenate([segments, colours], axis=2).reshape(-1, 7))

    def draw(self, target: moderngl.Framebuffer, view_projection: np.ndarray, name: str,
             on_top: bool = False) -> None:
        program = self.programs.get(PROGRAM)
        array = self._sets.array(name, program, lambda buffer: self.ctx.vertex_array(
            program, [(buffer, "3f 4f", "in_position", "in_colour")]))
        if array is None:
            return
        set_uniforms(program, {"u_view_projection": gl_matrix(view_projection)})
        flags = moderngl.BLEND | (moderngl.NOTHING if on_top else moderngl.DEPTH_TEST)
        with scoped(self.ctx, target, flags):
            self.ctx.blend_func = moderngl.DEFAULT_BLENDING
            array.render(moderngl.LINES, vertices=self._sets.count(name))

    def release(self) -> None:
        self._sets.release()
