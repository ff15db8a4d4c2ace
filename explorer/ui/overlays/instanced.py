"""Instanced drawing shared by the glyph and splat renderers: one mesh, named instance
sets (one buffer each), a vertex array per (set, program) remade after a shader reload."""

from __future__ import annotations

import moderngl
import numpy as np

from explorer.gl.program import ProgramCache


class InstancedMesh:
    """``mesh`` (vertices × floats) with attribute ``mesh_format``/``mesh_names``, drawn
    once per row of an instance set whose rows follow ``instance_format``."""

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache, program_name: str,
                 mesh: np.ndarray, mesh_format: str, mesh_names: tuple[str, ...],
                 instance_format: str, instance_names: tuple[str, ...],
                 indices: np.ndarray | None = None) -> None:
        self.ctx = ctx
        self.programs = programs
        self.program_name = program_name
        self._mesh = ctx.buffer(np.ascontiguousarray(mesh, np.float32).tobytes())
        self._indices = None if indices is None else ctx.buffer(
            np.ascontiguousarray(indices, np.int32).tobytes())
        self._mesh_layout = (mesh_format, *mesh_names)
        self._instance_layout = (instance_format + "/i", *instance_names)
        self._sets: dict[str, tuple[moderngl.Buffer, int]] = {}
        self._arrays: dict[str, moderngl.VertexArray] = {}

    def upload(self, name: str, rows: np.ndarray) -> None:
        """Replace instance set ``name`` with ``rows`` (count × floats per instance)."""
        rows = np.ascontiguousarray(rows, np.float32)
        self.discard(name)
        if len(rows):
            self._sets[name] = (self.ctx.buffer(rows.tobytes()), len(rows))

    def count(self, name: str) -> int:
        return self._sets[name][1] if name in self._sets else 0

    def program(self) -> moderngl.Program:
        return self.programs.get(self.program_name)

    def render(self, name: str, instances: int | None = None) -> None:
        """Draw the first ``instances`` rows of set ``name`` (all by default) with the
        uniforms already set on :meth:`program`."""
        if name not in self._sets:
            return
        buffer, count = self._sets[name]
        instances = count if instances is None else min(int(instances), count)
        if instances <= 0:
            return
        program = self.program()
        array = self._arrays.get(name)
        if array is None or array.program is not program:
            if array is not None:
                array.release()
            array = self.ctx.vertex_array(
                program, [(self._mesh, *self._mesh_layout), (buffer, *self._instance_layout)],
                index_buffer=self._indices, index_element_size=4)
            self._arrays[name] = array
        array.render(moderngl.TRIANGLES, instances=instances)

    def discard(self, name: str) -> None:
        if name in self._arrays:
            self._arrays.pop(name).release()
        if name in self._sets:
            self._sets.pop(name)[0].release()

    def release(self) -> None:
        for name in list(self._sets):
            self.discard(name)
        self._mesh.release()
        if self._indices is not None:
            self._indices.release()
