"""Fog: single scattering of the LPV's light and the direct light in a homogeneous medium
that fills the scene's box, ray-marched per pixel (``shaders/fog.glsl``, docs/MODEL.md
"Fog"). The numpy twin is :func:`explorer.lpv.twin.media.march_fog`.

The pass writes two ``rgba32f`` targets the display stage composes over the surfaces:
``direct`` (the direct light's in-scattered radiance in rgb, the transmittance to the
surface in alpha) and ``lpv`` (the LPV's in-scattered radiance in rgb). Its inputs are the
G-buffer (where each view ray ends), the RSM views (light records, ``light_records.py``)
with their shadow maps (the RSM atlas) and the accumulated grid of every cascade.
"""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from explorer.gl.fullscreen import FullscreenTriangle
from explorer.gl.program import ProgramCache, set_uniforms
from explorer.gl.targets import RenderTargets
from explorer.lpv.cascades import SampledGrid, cascade_uniforms
from explorer.lpv.passes.gbuffer import GBufferPass
from explorer.lpv.passes.light_records import LightRecordBuffer, ShadowMaps
from explorer.lpv.passes.textures import sh_defines
from explorer.scene.model import Scene
from explorer.scene.transforms import gl_matrix

TARGETS = ("fog_direct", "fog_lpv")
FIRST_GRID_UNIT = 3
"""Units 0..2: G-buffer position, shadow-map (atlas) position and normal; the grids
follow."""


@dataclass
class FogImages:
    """What the fog stage read back (docs/MODEL.md "Fog"), row 0 at the top."""

    transmittance: np.ndarray
    """``(H, W)``: exp(−σ_t·ℓ) along each pixel's view ray to its surface."""
    direct: np.ndarray
    """``(H, W, 3)``: the direct light's in-scattered radiance."""
    lpv: np.ndarray
    """``(H, W, 3)``: the LPV's in-scattered radiance."""

    def part(self, index: slice | tuple[slice, slice]) -> FogImages:
        """The images at ``index`` of their rows (and columns): a band of rows, a pixel,
        as the same images of a smaller frame (views, not copies)."""
        return FogImages(self.transmittance[index], self.direct[index], self.lpv[index])


@dataclass(frozen=True)
class Medium:
    """The homogeneous medium and how it is marched (the ``fog`` stage's ``Params`` makes
    it from the ``fog_*`` Settings)."""

    density: float
    """Extinction σ_t [1/m]."""
    albedo: float
    """Single-scattering albedo α = σ_s/σ_t."""
    g: float
    """Henyey–Greenstein asymmetry (0: isotropic)."""
    steps: int


def camera_rays(scene: Scene, size: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """``(eye, inverse view-projection)`` of the scene's camera for an image of ``size``:
    what the G-buffer pass rendered with, so that a background pixel's ray is the one its
    pixel centre would have had."""
    camera = scene.camera
    width, height = size
    projection = camera.projection_matrix(width / height, scene.bounds_min, scene.bounds_max)
    view_projection = projection @ camera.view_matrix()
    return np.asarray(camera.eye, np.float64), np.linalg.inv(view_projection)


class FogPass:
    """Full-screen pass writing the targets named in :data:`TARGETS`."""

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self._targets = RenderTargets(ctx, ("f4",) * len(TARGETS))
        self._triangle = FullscreenTriangle(ctx)
        self._lights = LightRecordBuffer(ctx)

    @property
    def targets(self) -> dict[str, moderngl.Texture]:
        """Target name -> texture (empty before the first run)."""
        return dict(zip(TARGETS, self._targets.textures))

    def run(self, gbuffer: GBufferPass, shadow: ShadowMaps, scene: Scene,
            grid: SampledGrid, medium: Medium, shader_filter: bool = False,
            rows: tuple[int, int] | None = None) -> None:
        """March every pixel's view ray (of the rows ``rows``, GL order, or all) through
        the medium, lit by ``grid`` (every cascade's accumulation, finest first) and the
        RSM views of ``shadow`` with their shadow maps. ``shader_filter``: interpolate
        the grid in the shader (the gather's probe, ``GatherPass.shader_filter``)."""
        self._targets.allocate(gbuffer.size)
        program = self.programs.get("fog.glsl", {**sh_defines(grid.sh_order),
                                                 "SH_SHADER_FILTER": int(shader_filter)})
        gbuffer.position.use(0)
        shadow.textures.position.use(1)
        shadow.textures.normal.use(2)
        light_count = self._lights.bind(shadow.views, shadow.tiles)
        eye, inverse = camera_rays(scene, gbuffer.size)
        set_uniforms(program, {
            "u_gbuffer_position": 0, "u_shadow_position": 1, "u_shadow_normal": 2,
            "u_light_count": light_count,
            "u_inverse_view_projection": gl_matrix(inverse),
            "u_camera_position": tuple(map(float, eye)),
            "u_medium_min": tuple(map(float, scene.bounds_min)),
            "u_medium_max": tuple(map(float, scene.bounds_max)),
            "u_fog_density": medium.density, "u_fog_albedo": medium.albedo,
            "u_fog_g": medium.g, "u_fog_steps": medium.steps,
            **grid.finest.spec.uniforms(),
            **cascade_uniforms(list(grid.cascades), FIRST_GRID_UNIT),
        })
        with self._targets.drawing(rows=rows):
            self._triangle.draw(program)

    def release(self) -> None:
        self._targets.release()
        self._triangle.release()
        self._lights.release()
