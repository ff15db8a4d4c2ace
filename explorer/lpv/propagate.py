"""Propagation of the light grid (docs/MODEL.md "Propagation", "Iterations and
accumulation") with the energy audit measured on the GPU alongside every step."""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from explorer.gl.program import ProgramCache, set_uniforms
from explorer.lpv.audit import AuditReducer, GridAudit
from explorer.lpv.geometry import GeometryVolume
from explorer.lpv.grid import GridSpec
from explorer.lpv.corrections import uniforms_read_by
from explorer.lpv.settings import Corrections
from explorer.lpv.textures import (
    LpvGrid,
    check_volume_array,
    copy_volume,
    default_context,
    dispatch_size,
    image_format_defines,
    per_context,
    programs_for,
    sh_defines,
    sh_order_of,
)


@dataclass
class PropagationOutput:
    accumulated: LpvGrid
    """acc_N = Σ grid_t. Owned by the pass: valid until its next run or release."""
    steps: list[np.ndarray] | None
    """grid_0..grid_N as (3, N, N, N, 4) arrays when keep_steps. In place, grid_t is the
    light step t added (acc_t − acc_{t−1}), so Σ grid_t = acc_N in both modes."""
    audit: GridAudit


def copy_grid(programs: ProgramCache, source: LpvGrid, target: LpvGrid) -> None:
    for source_volume, target_volume in zip(source.volumes, target.volumes):
        copy_volume(programs, source_volume.texture, target_volume)


class PropagatePass:
    """Propagates an injected grid ``iterations`` times (``shaders/propagate.glsl``).

    Ping-pong (``corrections.ping_pong``): grid_t = P(grid_{t−1}) alternates between two
    scratch grids and is added into the accumulation grid by the same dispatch. In place
    (the DX11 shader): the accumulation grid is read and written by one dispatch per step,
    a data race kept on purpose. Either way the dispatch also sums the step's audit terms
    (for in place: of what the racing invocations actually read and added).

    GPU memory besides the input: three grids (ping, pong, accumulation) in the input's
    format and 48 bytes per cell of audit records (≈100 MB each at 128³ in rgba32f).
    """

    GEOMETRY_UNIT = 6
    ALBEDO_UNIT = 7
    STAGE = "propagate"
    """Its program reads this stage's correction switches."""

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self.audit = AuditReducer(ctx, programs)
        self._grids: dict[str, LpvGrid] = {}

    def _scratch(self, name: str, resolution: int, fmt: str, sh_order: int) -> LpvGrid:
        grid = self._grids.get(name)
        if grid is None or grid.resolution != resolution or grid.format != fmt or \
                grid.sh_order != sh_order:
            if grid is not None:
                grid.release()
            grid = self._grids[name] = LpvGrid(self.ctx, resolution, fmt, sh_order)
        return grid

    def run(self, injected: LpvGrid, spec: GridSpec, corrections: Corrections,
            iterations: int, geometry: GeometryVolume | None = None,
            keep_steps: bool = False, bounces: int = 1) -> PropagationOutput:
        """``bounces`` 2: the geometry volume reflects the light it blocks
        (``shaders/reflection.glsl``, docs/MODEL.md "More bounces"); needs ``geometry``.
        The injected grid's ``sh_order`` selects L1 or L2 propagation."""
        n, fmt, order = spec.resolution, injected.format, injected.sh_order
        if bounces not in (1, 2) or isinstance(bounces, bool):
            raise ValueError(f"bounces must be 1 or 2, got {bounces!r}")
        if bounces == 2 and geometry is None:
            raise ValueError("bounces=2 reflects the light the geometry volume blocks: pass "
                             "a geometry volume")
        if injected.resolution != n:
            raise ValueError(f"the injected grid has {injected.resolution}^3 cells but the "
                             f"grid spec has {n}^3")
        if geometry is not None and geometry.resolution != n:
            raise ValueError(f"the geometry volume belongs to a {geometry.resolution}^3 grid, "
                             f"the light grid has {n}^3 cells")
        if int(iterations) != iterations or iterations < 0:
            raise ValueError(f"iterations must be a whole number >= 0, got {iterations!r}")
        iterations = int(iterations)

        accumulated = self._scratch("accumulated", n, fmt, order)
        copy_grid(self.programs, injected, accumulated)
        self.audit.begin(n, iterations + 2)
        self.audit.measure_flux(0, injected)
        steps = [injected.read()] if keep_steps else None

        program = self.programs.get("propagate.glsl",
                                    {**image_format_defines(fmt), **sh_defines(order)})
        set_uniforms(program, {
            **spec.uniforms(), **corrections.as_uniforms(),
            "u_source_r": 0, "u_source_g": 1, "u_source_b": 2,
            "u_geometry": self.GEOMETRY_UNIT, "u_use_geometry": geometry is not None,
            "u_geometry_albedo": self.ALBEDO_UNIT, "u_reflect": bounces == 2,
        }, reads=uniforms_read_by(self.STAGE))
        groups = dispatch_size(n)
        source = injected
        previous = steps[0] if keep_steps else None
        for step in range(1, iterations + 1):
            if corrections.ping_pong:
                target = self._scratch("ping" if step % 2 else "pong", n, fmt, order)
            else:
                # The race: the dispatch reads its neighbours from the grid it writes.
                target = accumulated
            source.use_as_textures(0)
            if geometry is not None:
                geometry.use_as_texture(self.GEOMETRY_UNIT)
                geometry.albedo.texture.use(self.ALBEDO_UNIT)
            target.bind_images(0)
            accumulated.bind_images(3)
            self.audit.bind()
            program.run(*groups)
            self.ctx.memory_barrier()
            self.audit.sum_cell_records(step)
            if keep_steps:
                current = target.read()
                steps.append(current if corrections.ping_pong else current - previous)
                previous = current
            source = target
        self.audit.measure_flux(iterations + 1, accumulated)

        sums = self.audit.read()
        audit = GridAudit(
            injected=sums[0, 0:3],
            per_step=sums[: iterations + 1, 0:3],
            border_loss=sums[1: iterations + 1, 3:6],
            clamp_gain=sums[1: iterations + 1, 6:9],
            occluded=sums[1: iterations + 1, 9:12],
            accumulated=sums[iterations + 1, 0:3],
            reflected=sums[1: iterations + 1, 12:15],
            blocked=sums[1: iterations + 1, 15:18],
        )
        return PropagationOutput(accumulated=accumulated, steps=steps, audit=audit)

    def release(self) -> None:
        for grid in self._grids.values():
            grid.release()
        self._grids.clear()
        self.audit.release()


def propagate_with_audit(grid: np.ndarray, corrections: Corrections | None = None,
                         iterations: int = 1, geometry: np.ndarray | None = None,
                         ctx: moderngl.Context | None = None, fmt: str = "rgba32f",
                         geometry_albedo: np.ndarray | None = None, bounces: int = 1,
                         ) -> tuple[list[np.ndarray], np.ndarray, GridAudit]:
    """GPU propagation of a numpy grid: (grid_0..grid_N, acc_N, audit). The last axis of
    ``grid`` (4 or 9 coefficients) selects L1 or L2.
    ``geometry_albedo``: the geometry volume's ``(N+1)³×4`` albedo sums (``bounces`` 2)."""
    grid = np.asarray(grid)
    if grid.ndim != 5 or grid.shape[0] != 3:
        raise ValueError(f"grid must have shape (3, N, N, N, 4) or (3, N, N, N, 9), got "
                         f"{grid.shape}")
    n = grid.shape[1]
    order = sh_order_of(grid.shape[4])
    grid = check_volume_array(grid, n, "grid", channels=3, coefficients=grid.shape[4])
    corrections = corrections or Corrections()
    ctx = ctx or default_context()
    spec = GridSpec((0.0, 0.0, 0.0), 1.0, n)
    injected = LpvGrid(ctx, n, fmt, order)
    volume = None
    try:
        injected.write(grid)
        if geometry is not None:
            volume = GeometryVolume(ctx, n, fmt)
            volume.write(check_volume_array(geometry, n + 1, "geometry"),
                         None if geometry_albedo is None else
                         check_volume_array(geometry_albedo, n + 1, "geometry_albedo"))
        propagator = per_context(ctx, "propagate",
                                 lambda: PropagatePass(ctx, programs_for(ctx)))
        output = propagator.run(injected, spec, corrections, iterations, volume,
                                keep_steps=True, bounces=bounces)
        return output.steps, output.accumulated.read(), output.audit
    finally:
        injected.release()
        if volume is not None:
            volume.release()


def propagate(grid: np.ndarray, corrections: Corrections | None = None, iterations: int = 1,
              geometry: np.ndarray | None = None, ctx: moderngl.Context | None = None,
              fmt: str = "rgba32f") -> list[np.ndarray]:
    """GPU propagation of a ``(3, N, N, N, 4)`` (L1) or ``(3, N, N, N, 9)`` (L2) grid:
    grid_0..grid_N as float32 arrays (``geometry``: an optional ``(N+1, N+1, N+1, 4)`` L1
    geometry volume)."""
    return propagate_with_audit(grid, corrections, iterations, geometry, ctx, fmt)[0]
