"""GPU buffers the overlay renderers share: :class:`BufferSets` (named vertex or instance
buffers, each with its vertex array, remade after a shader reload) and
:class:`InstancedMesh` (one mesh drawn once per row of a named instance set)."""

from __future__ import annotations

from collections.abc import Callable

import moderngl
import numpy as np

from explorer.gl.program import ProgramCache


class BufferSets:
    """Named float32 buffers of rows and the vertex array that draws each."""

    def __init__(self, ctx: moderngl.Context) -> None:
        self.ctx = ctx
        self._sets: dict[str, tuple[moderngl.Buffer, int]] = {}
        self._arrays: dict[str, moderngl.VertexArray] = {}

    def put(self, name: str, rows: np.ndarray) -> None:
        """Replace set ``name`` with ``rows`` (count × floats); an empty one is dropped."""
        rows = np.ascontiguousarray(rows, np.float32)
        self.discard(name)
        if len(rows):
            self._sets[name] = (self.ctx.buffer(rows.tobytes()), len(rows))

    def count(self, name: str) -> int:
        return self._sets[name][1] if name in self._sets else 0

    def array(self, name: str, program: moderngl.Program,
              build: Callable[[moderngl.Buffer], moderngl.VertexArray]
              ) -> moderngl.VertexArray | None:
        """The vertex array of set ``name`` for ``program`` (made by ``build(buffer)``),
        or None when the set is empty."""
        if name not in self._sets:
            return None
        array = self._arrays.get(name)
        if array is None or array.program is not program:
            if array is not None:
                array.release()
            array = self._arrays[name] = build(self._sets[name][0])
        return array

    def discard(self, name: str) -> None:
        if name in self._arrays:
            self._arrays.pop(name).release()
        if name in self._sets:
            self._sets.pop(name)[0].release()

    def release(self) -> None:
        for name in list(self._sets):
            self.discard(name)


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
        self._instances = BufferSets(ctx)

    def upload(self, name: str, rows: np.ndarray) -> None:
        self._instances.put(name, rows)

    def count(self, name: str) -> int:
        return self._instances.count(name)

    def program(self) -> moderngl.Program:
        return self.programs.get(self.program_name)

    def render(self, name: str, instances: int | None = None) -> None:
        """Draw the first ``instances`` rows of set ``name`` (all by default) with the
        uniforms already set on :meth:`program`."""
        count = self.count(name)
        instances = count if instances is None else min(int(instances), count)
        if instances <= 0:
            return
        program = self.program()
        array = self._instances.array(name, program, lambda buffer: self.ctx.vertex_array(
            program, [(self._mesh, *self._mesh_layout), (buffer, *self._instance_layout)],
            index_buffer=self._indices, index_element_size=4))
        array.render(moderngl.TRIANGLES, instances=instances)

    def release(self) -> None:
        self._instances.release()
        self._mesh.release()
        if self._indices is not None:
            self._indices.release()
