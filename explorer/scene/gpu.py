"""The scene's triangles on the GPU, shared by the RSM and G-buffer passes."""

from __future__ import annotations

import moderngl

from explorer.scene.model import Scene

VERTEX_FORMAT = ("3f 3f 3f", "in_position", "in_normal", "in_albedo")


class SceneBuffers:
    """One vertex buffer of interleaved position, normal, albedo; a vertex array per
    program that draws it."""

    def __init__(self, ctx: moderngl.Context, scene: Scene) -> None:
        self.ctx = ctx
        self.scene = scene
        self.vertex_count = len(scene.positions)
        self.buffer = ctx.buffer(scene.vertex_bytes())
        self._arrays: dict[int, moderngl.VertexArray] = {}

    def draw(self, program: moderngl.Program) -> None:
        key = id(program)
        vertex_array = self._arrays.get(key)
        if vertex_array is None or vertex_array.program is not program:
            # attributes a program does not use are optimised away: skip them with "x"
            _, *names = VERTEX_FORMAT
            kept = [name if name in program else None for name in names]
            layout = " ".join("3f" if name else "12x" for name in kept)
            vertex_array = self.ctx.vertex_array(
                program, [(self.buffer, layout, *[n for n in kept if n])])
            self._arrays[key] = vertex_array
        vertex_array.render(moderngl.TRIANGLES)

    def release(self) -> None:
        for vertex_array in self._arrays.values():
            vertex_array.release()
        self._arrays.clear()
        self.buffer.release()
