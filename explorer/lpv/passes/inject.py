"""Light injection: VPLs -> intensity SH in the light grid (docs/MODEL.md "Injection").

Two GPU paths give the same grid up to float summation order:

* ``"points"``: one point per VPL, layered rendering with additive ONE,ONE blending
  (``shaders/inject_points.glsl``), then a copy of the layers into the 3D textures;
* ``"compute"``: the compute-shader gather the DX12 write-up proposes: bin the VPLs into
  per-cell linked lists, then one invocation per cell sums its list
  (``shaders/inject_compute.glsl``).

The output grid's ``sh_order`` picks the lobe: L1 (4 coefficients) or L2 (9; the point
path draws one point per texel group, docs/MODEL.md "L2 option").
"""

from __future__ import annotations

from collections.abc import Iterator

import moderngl
import numpy as np

from explorer.gl.program import ProgramCache, set_uniforms
from explorer.lpv.corrections import uniforms_read_by
from explorer.lpv.grid import GridSpec, shape_text
from explorer.lpv.passes.textures import (
    SH_GROUPS,
    LayeredTarget,
    LpvGrid,
    copied_apart,
    copy_volume,
    copy_volumes,
    default_context,
    dispatch_size,
    draw_points_additively,
    image_format_defines,
    per_context,
    point_batches,
    programs_for,
    sh_defines,
)
from explorer.lpv.settings import INJECTION_MODES, Corrections
from explorer.lpv.vpl import VplArrays, VplTextures

_VPL_UNITS = {"u_vpl_position": 0, "u_vpl_normal": 1, "u_vpl_flux": 2}
CHANNELS = 3
"""Volumes of an :class:`LpvGrid` (one per colour channel): the point path copies each."""


def bind_vpl_textures(vpls: VplTextures) -> dict[str, int]:
    """Bind the VPL textures to units 0..2; returns the sampler uniforms for vpl.glsl."""
    for texture, unit in zip((vpls.position, vpls.normal, vpls.flux), _VPL_UNITS.values()):
        texture.use(unit)
    return dict(_VPL_UNITS)


def vpl_count(vpls: VplTextures) -> int:
    width, height = vpls.size
    return int(width) * int(height)


class InjectPass:
    """Injects a VPL texture set into an :class:`LpvGrid` (the grid is overwritten)."""

    STAGE = "inject"
    """Its programs that write the grid read this stage's correction switches."""

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self._layers: LayeredTarget | None = None
        self._heads: moderngl.Buffer | None = None
        self._links: moderngl.Buffer | None = None
        self._uniforms: dict[tuple, dict[str, object]] = {}

    @staticmethod
    def unit_count(mode: str, cells: tuple[int, int, int], sh_order: int,
                   vpls: int = 0) -> int:
        """Units of :meth:`run_units` of ``vpls`` VPLs into a grid of ``cells`` and
        ``sh_order``: the point path's draws (:func:`point_batches`: a larger RSM's in
        several), then one copy per channel's volume when its volumes are copied apart
        (:func:`copied_apart`: a 64³ copy is a frame's share on llvmpipe); else one."""
        if mode != "points":
            return 1
        shape = (cells[0], cells[1], cells[2] * SH_GROUPS[sh_order])
        return len(point_batches(vpls)) + (CHANNELS if copied_apart(shape) else 0)

    def run(self, vpls: VplTextures, spec: GridSpec, corrections: Corrections,
            mode: str, out: LpvGrid, offset_cells: float = 0.0) -> None:
        """``offset_cells``: inject each VPL at p + offset_cells·cell_size·n
        (docs/MODEL.md "Injection")."""
        for _ in self.run_units(vpls, spec, corrections, mode, out, offset_cells):
            pass

    def run_units(self, vpls: VplTextures, spec: GridSpec, corrections: Corrections,
                  mode: str, out: LpvGrid, offset_cells: float = 0.0) -> Iterator[None]:
        """:meth:`run`'s work as a generator of :meth:`unit_count` units, yielding after
        every unit but its last (the same GL work in the same order: the same grid)."""
        check_offset_cells(offset_cells)
        if mode not in INJECTION_MODES:
            raise ValueError(f"injection mode must be one of {INJECTION_MODES}, got {mode!r}")
        if out.cells != spec.cells:
            raise ValueError(f"the output grid has {shape_text(out.cells)} cells but the "
                             f"grid spec has {shape_text(spec.cells)}")
        samplers = bind_vpl_textures(vpls)
        # one dict per grid, switches and offset (never changed once made): a frame's
        # injection sets it again without stamping it (set_uniforms skips its last dict)
        key = (spec, corrections, float(offset_cells))
        uniforms = self._uniforms.get(key)
        if uniforms is None:
            if len(self._uniforms) >= 16:
                self._uniforms.clear()
            uniforms = self._uniforms[key] = {
                **spec.uniforms(), **corrections.as_uniforms(), **samplers,
                "u_injection_offset": float(offset_cells) * spec.cell_size}
        if mode == "points":
            yield from self._inject_points(vpls, uniforms, out)
        else:
            self._inject_compute(vpls, uniforms, out)

    def _inject_points(self, vpls: VplTextures, uniforms: dict, out: LpvGrid
                       ) -> Iterator[None]:
        """The draws into the layers (a batch each), then each layer stack's copy: a unit
        each (the copies apart only for a large grid)."""
        n, depth = out.cells, out.groups * out.cells[2]
        layers = self._layers
        if layers is None or layers.shape != n[:2] + (depth,) or \
                layers.format != out.format:
            if layers is not None:
                layers.release()
            layers = self._layers = LayeredTarget(self.ctx, n, 3, out.format, depth=depth)
        for first, count in point_batches(vpl_count(vpls)):
            if first:
                yield   # the layers keep the sums; the next batch binds all it reads again
                bind_vpl_textures(vpls)
            program = self.programs.get("inject_points.glsl", sh_defines(out.sh_order))
            set_uniforms(program, uniforms, reads=uniforms_read_by(self.STAGE))
            draw_points_additively(self.ctx, program, layers, count, clear=not first,
                                   first=first)
        if not copied_apart(layers.shape):
            copy_volumes(self.programs, layers.layers, out.volumes)
            return
        for stack, volume in zip(layers.layers, out.volumes):
            yield   # the layers keep the sums: each copy may run in a later frame
            copy_volume(self.programs, stack, volume)

    def _inject_compute(self, vpls: VplTextures, uniforms: dict, out: LpvGrid) -> None:
        n, count = out.cells, vpl_count(vpls)
        self._heads = _sized_buffer(self.ctx, self._heads, 4 * n[0] * n[1] * n[2])
        self._links = _sized_buffer(self.ctx, self._links, 4 * count)
        self._heads.clear()  # 0 = empty list
        self._heads.bind_to_storage_buffer(0)
        self._links.bind_to_storage_buffer(1)

        link = self.programs.get("inject_compute.glsl", {"INJECT_STAGE": 0})
        set_uniforms(link, uniforms)  # bins VPLs into cells: no correction applies yet
        link.run(-(-count // 64))
        self.ctx.memory_barrier()

        gather = self.programs.get("inject_compute.glsl",
                                   {"INJECT_STAGE": 1, **image_format_defines(out.format),
                                    **sh_defines(out.sh_order)})
        out.bind_images(0, read=False, write=True)
        # images: units 0..2 by binding
        set_uniforms(gather, uniforms, reads=uniforms_read_by(self.STAGE))
        gather.run(*dispatch_size(n))
        self.ctx.memory_barrier()

    def release_between_runs(self, min_bytes: int) -> int:
        """Release the point draws' layers (they hold the sums only while an injection is
        in progress) when they are ``min_bytes`` or more; the next injection makes them
        anew. Returns the bytes released."""
        layers = self._layers
        if layers is None or layers.nbytes < min_bytes:
            return 0
        self._layers = None
        layers.release()
        return layers.nbytes

    def release(self) -> None:
        for resource in (self._layers, self._heads, self._links):
            if resource is not None:
                resource.release()
        self._layers = self._heads = self._links = None


def check_offset_cells(offset_cells: float) -> float:
    """``offset_cells`` as a float; a ValueError unless it is finite and >= 0."""
    value = float(offset_cells)
    if not (np.isfinite(value) and value >= 0.0):
        raise ValueError(f"the injection offset must be a finite number of cells >= 0, got "
                         f"{offset_cells!r}")
    return value


def _sized_buffer(ctx: moderngl.Context, buffer: moderngl.Buffer | None,
                  size: int) -> moderngl.Buffer:
    """``buffer`` if it holds at least ``size`` bytes, else a new one (the old is freed)."""
    if buffer is not None and buffer.size >= size:
        return buffer
    if buffer is not None:
        buffer.release()
    return ctx.buffer(reserve=max(size, 4))


def inject(vpls: VplArrays, spec: GridSpec, corrections: Corrections | None = None,
           mode: str = "points", ctx: moderngl.Context | None = None,
           fmt: str = "rgba32f", offset_cells: float = 0.0, sh_order: int = 1) -> np.ndarray:
    """Inject VPL arrays on the GPU and return the grid as float32 ``(3, nx, ny, nz, C)``,
    C = 4 (``sh_order`` 1, L1) or 9 (``sh_order`` 2, L2).

    ``ctx`` None uses a headless context created on first use. VPLs outside the grid are
    dropped. ``fmt`` is the grid's texture format (``rgba32f`` or ``rgba16f``);
    ``offset_cells`` moves each VPL that many cells along its normal first.
    """
    if not isinstance(vpls, VplArrays):
        raise TypeError(f"vpls must be a VplArrays, got {type(vpls).__name__}")
    if not isinstance(spec, GridSpec):
        raise TypeError(f"spec must be a GridSpec, got {type(spec).__name__}")
    corrections = corrections or Corrections()
    ctx = ctx or default_context()
    grid = LpvGrid(ctx, spec.cells, fmt, sh_order)
    try:
        if vpls.count == 0:
            return np.zeros((3,) + spec.cells + (grid.coefficients,), np.float32)
        textures = VplTextures.from_arrays(ctx, vpls)
        try:
            injector = per_context(ctx, "inject", lambda: InjectPass(ctx, programs_for(ctx)))
            injector.run(textures, spec, corrections, mode, grid, offset_cells)
            return grid.read()
        finally:
            textures.release()
    finally:
        grid.release()
