"""Final gather: direct light, LPV indirect light and exposure (docs/MODEL.md "Final
gather"); the display pass (explorer/lpv/display.py) encodes the result for the screen.

At a visible point with normal n and albedo a the accumulated grid is sampled trilinearly;
the irradiance is E = max(<s, lobe(-n)>, 0) / cell_size² (L1 or L2 lobe after the grid's
SH order) and the indirect radiance a/π·E (optionally damped by the directional
derivative along n). The direct radiance is a/π times the light's irradiance I·cos θ/r²
(spot, times the cone's falloff f) or E_L·cos θ (directional), shadowed with the RSM's
depth (normal.w) through a PCF box ``shadow_kernel`` texels wide.
"""

from __future__ import annotations

import moderngl

from explorer.gl.fullscreen import FullscreenTriangle
from explorer.gl.program import ProgramCache, set_uniforms
from explorer.lpv.cascades import CascadeInput, cascade_uniforms
from explorer.lpv.gbuffer import GBufferPass
from explorer.lpv.grid import GridSpec
from explorer.lpv.rsm import LightView
from explorer.lpv.settings import DEFAULT_SHADOW_KERNEL
from explorer.lpv.textures import sh_defines
from explorer.lpv.vpl import VplTextures

TARGETS = ("direct", "indirect", "final", "received")


class GatherPass:
    """Full-screen pass writing the ``rgba32f`` targets named in :data:`TARGETS`."""

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self.size: tuple[int, int] = (0, 0)
        self.targets: dict[str, moderngl.Texture] = {}
        self._framebuffer: moderngl.Framebuffer | None = None
        self._triangle = FullscreenTriangle(ctx)
        self._empty_grid: moderngl.Texture3D | None = None

    def _allocate(self, size: tuple[int, int]) -> None:
        if size == self.size:
            return
        self._free_targets()
        for name in TARGETS:
            texture = self.ctx.texture(size, 4, dtype="f4")
            texture.filter = (moderngl.NEAREST, moderngl.NEAREST)
            self.targets[name] = texture
        self._framebuffer = self.ctx.framebuffer([self.targets[n] for n in TARGETS])
        self.size = size

    def run(self, gbuffer: GBufferPass, shadow: VplTextures, light: LightView,
            grid_textures, spec: GridSpec, exposure: float, indirect_only: bool,
            damping: bool = False, cascades: list[CascadeInput] | None = None,
            sh_order: int = 1, shadow_kernel: int = DEFAULT_SHADOW_KERNEL) -> None:
        """``grid_textures``: the accumulated grid's r, g, b 3D textures (linear filter,
        clamped), or None for direct light only. ``damping``: the directional-derivative
        damping of the indirect irradiance (docs/MODEL.md "Final gather"), single grid only.
        ``cascades``: several nested grids (finest first, docs/MODEL.md "Cascades") sampled
        instead of ``grid_textures``; None or one cascade = the single grid. ``sh_order``:
        the SH order of the grid(s) (their texel layout, explorer/lpv/textures.py).
        ``shadow_kernel``: width of the PCF box in shadow-map texels (1 = one hard test)."""
        self._allocate(gbuffer.size)
        program = self.programs.get("gather.glsl", sh_defines(sh_order))
        gbuffer.position.use(0)
        gbuffer.normal.use(1)
        gbuffer.albedo.use(2)
        shadow.position.use(3)
        shadow.normal.use(4)
        if grid_textures is None and cascades:
            grid_textures = cascades[0].textures
        if grid_textures is None:
            grid_textures = (self._empty(),) * 3
        for unit, texture in enumerate(grid_textures, start=5):
            texture.use(unit)
        values = {
            "u_gbuffer_position": 0, "u_gbuffer_normal": 1, "u_gbuffer_albedo": 2,
            "u_shadow_position": 3, "u_shadow_normal": 4,
            "u_lpv_r": 5, "u_lpv_g": 6, "u_lpv_b": 7,
            "u_shadow_texel": light.texel_world_size,
            "u_shadow_kernel": int(shadow_kernel),
            "u_exposure": float(exposure),
            "u_indirect_only": int(indirect_only),
            "u_has_grid": int(grid_textures[0] is not self._empty_grid),
            "u_gather_damping": int(damping),
            **light.uniforms(),
            **spec.uniforms(),
            **self._cascade_uniforms(cascades, grid_textures, spec),
        }
        set_uniforms(program, values)
        with self.ctx.scope(self._framebuffer, enable_only=moderngl.NOTHING):
            self._framebuffer.viewport = (0, 0, *self.size)
            self._triangle.draw(program)

    CASCADE_FIRST_UNIT = 8

    @classmethod
    def _cascade_uniforms(cls, cascades: list[CascadeInput] | None, grid_textures,
                          spec: GridSpec) -> dict[str, object]:
        """``cascades.glsl`` uniforms. With a single grid its sampler arrays point at the
        single grid's units 5..7 (a sampler3D may not share a unit with the G-buffer's
        2D samplers, even unused) and the count is 1, which selects the single-grid code."""
        if cascades is None or len(cascades) <= 1:
            return cascade_uniforms([CascadeInput(spec, ())], 5)
        return cascade_uniforms(cascades, cls.CASCADE_FIRST_UNIT)

    def _empty(self) -> moderngl.Texture3D:
        if self._empty_grid is None:
            self._empty_grid = self.ctx.texture3d((1, 1, 1), 4, dtype="f4")
        return self._empty_grid

    def _free_targets(self) -> None:
        if self._framebuffer is not None:
            self._framebuffer.release()
            self._framebuffer = None
        for texture in self.targets.values():
            texture.release()
        self.targets, self.size = {}, (0, 0)

    def release(self) -> None:
        self._free_targets()
        self._triangle.release()
        if self._empty_grid is not None:
            self._empty_grid.release()
            self._empty_grid = None
