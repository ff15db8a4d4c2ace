"""The least a propagation needs (:class:`BaselinePropagatePass`): what ``lpv-explorer
bench`` times :class:`explorer.lpv.passes.propagate.PropagatePass` against."""

from __future__ import annotations

import moderngl

from explorer.gl.program import ProgramCache, set_uniforms
from explorer.lpv.grid import GridSpec
from explorer.lpv.passes.geometry import GeometryVolume
from explorer.lpv.passes.propagate import PropagatePass, copy_grid
from explorer.lpv.passes.textures import LpvGrid, dispatch_size, image_format_defines


class BaselinePropagatePass:
    """The least a propagation needs (``shaders/propagate_minimal.glsl``): the corrected
    L1 ping-pong step, each neighbour's five faces written out with the generated
    constants (three ``texelFetch`` per neighbour, four more of the geometry volume when
    there is one), the three target images written and the three accumulation images added
    into, one memory barrier per step; no switches, no audit. It is the baseline
    ``lpv-explorer bench`` times :class:`PropagatePass` against in the same run (one
    ``finish`` around all steps); with the corrected switches both give the same
    accumulation."""

    GEOMETRY_UNIT = PropagatePass.GEOMETRY_UNIT

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self._grids: dict[str, LpvGrid] = {}

    def run(self, injected: LpvGrid, spec: GridSpec, iterations: int,
            geometry: GeometryVolume | None = None) -> LpvGrid:
        """acc_N of ``iterations`` steps (owned by the pass, valid until its next run)."""
        n, fmt = spec.cells, injected.format
        if injected.sh_order != 1:
            raise ValueError("the baseline propagation is L1 only (sh_order 1)")
        grids = {}
        for name in ("ping", "pong", "accumulated"):
            grid = self._grids.get(name)
            if grid is None or grid.cells != n or grid.format != fmt:
                if grid is not None:
                    grid.release()
                grid = self._grids[name] = LpvGrid(self.ctx, n, fmt)
            grids[name] = grid
        accumulated = grids["accumulated"]
        copy_grid(self.programs, injected, accumulated)
        program = self.programs.get("propagate_minimal.glsl", {
            **image_format_defines(fmt), "PROPAGATE_GEOMETRY": int(geometry is not None)})
        set_uniforms(program, {"u_grid_cells": n, "u_source_r": 0, "u_source_g": 1,
                               "u_source_b": 2, "u_geometry": self.GEOMETRY_UNIT})
        groups = dispatch_size(n)
        source = injected
        for step in range(1, int(iterations) + 1):
            target = grids["ping" if step % 2 else "pong"]
            source.use_as_textures(0)
            if geometry is not None:
                geometry.use_as_texture(self.GEOMETRY_UNIT)
            target.bind_images(0)
            accumulated.bind_images(3)
            program.run(*groups)
            self.ctx.memory_barrier()
            source = target
        return accumulated

    def release(self) -> None:
        for grid in self._grids.values():
            grid.release()
        self._grids.clear()
