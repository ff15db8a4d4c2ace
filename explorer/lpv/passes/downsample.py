"""RSM downsample (``Settings.downsample``): ``"average"`` or the DX11 article's
``"brightest"`` kernel over blocks of ``downsample_factor``² texels (shaders/downsample.glsl).

A downsampled VPL stands for every texel of its block, so its flux is the SUM of the
block's flux (``"average"`` conserves the RSM's flux exactly) and its surfel covers the
block: ``texel_area`` grows by ``factor²``. ``"brightest"`` keeps only the texels near the
brightest one's grid cell; the flux of the others is dropped (visible in the audit as
``rsm`` > injected).
"""

from __future__ import annotations

import moderngl

from explorer.gl.fullscreen import FullscreenTriangle
from explorer.gl.program import ProgramCache, set_uniforms
from explorer.gl.targets import RenderTargets
from explorer.lpv.grid import GridSpec
from explorer.lpv.passes.rsm import LightView
from explorer.lpv.vpl import VplTextures

MODES = {"average": 1, "brightest": 2}


def downsampled_size(size: tuple[int, int], factor: int) -> tuple[int, int]:
    """``ceil(size / factor)``: partial blocks at the edges still make a VPL."""
    return tuple(-(-int(s) // int(factor)) for s in size)


class DownsamplePass:
    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self._targets = RenderTargets(ctx, ("f4",) * 3)
        self._targets.keep_sizes = 0        # follows the RSM's size (rsm.py), not a drag's
        self._triangle = FullscreenTriangle(ctx)

    @property
    def size(self) -> tuple[int, int]:
        return self._targets.size

    def run(self, vpls: VplTextures, mode: str, factor: int, spec: GridSpec,
            light: LightView) -> VplTextures:
        if mode not in MODES:
            raise ValueError(f"downsample mode must be one of {tuple(MODES)}, got {mode!r}")
        if int(factor) < 1:
            raise ValueError(f"downsample_factor must be at least 1, got {factor}")
        self._targets.allocate(downsampled_size(vpls.size, factor))
        program = self.programs.get("downsample.glsl")
        vpls.position.use(0)
        vpls.normal.use(1)
        vpls.flux.use(2)
        set_uniforms(program, {
            "u_rsm_position": 0, "u_rsm_normal": 1, "u_rsm_flux": 2,
            "u_factor": int(factor), "u_mode": MODES[mode],
            "u_light_direction": tuple(map(float, light.direction)),
            **spec.uniforms(),
        })
        with self._targets.drawing():
            self._triangle.draw(program)
        position, normal, flux = self._targets.textures
        return VplTextures(position, normal, flux, texel_area=vpls.texel_area * factor * factor,
                           projection=vpls.projection)

    def release(self) -> None:
        self._targets.release()
        self._triangle.release()
