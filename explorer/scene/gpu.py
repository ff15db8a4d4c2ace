"""The scene's triangles on the GPU, shared by the RSM and G-buffer passes. Moving an
object rewrites only that object's corners (:meth:`SceneBuffers.show`)."""

from __future__ import annotations

import moderngl

from explorer.scene.model import Scene

VERTEX_FORMAT = ("3f 3f 3f", "in_position", "in_normal", "in_albedo")
VERTEX_BYTES = 36
"""Bytes of one corner: position, normal, albedo (three float32 each)."""


class SceneBuffers:
    """One vertex buffer of interleaved position, normal, albedo; a vertex array per
    program that draws it."""

    def __init__(self, ctx: moderngl.Context, scene: Scene) -> None:
        self.ctx = ctx
        self.scene = scene
        self.vertex_count = len(scene.positions)
        self.buffer = ctx.buffer(scene.vertex_bytes())
        self._arrays: dict[int, moderngl.VertexArray] = {}
        self._pose = dict(scene.pose)

    def show(self, scene: Scene) -> int:
        """Make the buffer hold ``scene``'s corners: ``scene`` is the buffer's scene posed
        (``Scene.posed``) another way, and only the objects whose transform changed are
        written again. Returns the number of corners written."""
        if len(scene.positions) != self.vertex_count:
            raise ValueError(f"scene {scene.name!r} has {len(scene.positions)} corners, the "
                             f"buffer {self.vertex_count}: make new SceneBuffers for it")
        pose = dict(scene.pose)
        written = 0
        for obj in scene.objects:
            if pose.get(obj.name) != self._pose.get(obj.name):
                self.buffer.write(scene.vertex_bytes(obj.first, obj.stop),
                                  offset=obj.first * VERTEX_BYTES)
                written += obj.count
        self._pose = pose
        self.scene = scene
        return written

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
