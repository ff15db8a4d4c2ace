"""Final gather: direct light and LPV indirect light, linear (docs/MODEL.md "Final
gather"); exposure and display encoding are the display pass's (explorer/lpv/passes/display.py).

At a visible point with normal n and albedo a the accumulated grid is sampled trilinearly;
the irradiance is E = max(<s, lobe(-n)>, 0) / cell_size² (L1 or L2 lobe after the grid's
SH order) and the indirect radiance a/π·E (optionally damped by the directional
derivative along n). The direct radiance is a/π times the irradiance of every RSM view,
I·cos θ/r² (spot, times the cone's falloff f; a point light's face for the points it
holds) or E_L·cos θ (directional), times its colour, each shadowed with its own RSM's
depth (normal.w) through a PCF box ``shadow_kernel`` texels wide (docs/MODEL.md "Several
lights"; the views' records: explorer/lpv/passes/light_records.py). With ``Glossy`` the glossy
march (docs/MODEL.md "Glossy reflections") adds to the indirect radiance.
"""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from explorer.gl.fullscreen import FullscreenTriangle
from explorer.gl.program import ProgramCache, set_uniforms
from explorer.gl.targets import RenderTargets
from explorer.lpv.audit import rgb_sums
from explorer.lpv.cascades import CascadeInput, SampledGrid, bind_cascades, cascade_uniforms
from explorer.lpv.corrections import uniforms_read_by
from explorer.lpv.grid import GridSpec
from explorer.lpv.passes.gbuffer import GBufferPass
from explorer.lpv.passes.light_records import LightRecordBuffer, ShadowMaps
from explorer.lpv.passes.textures import per_context, sh_defines
from explorer.lpv.settings import DEFAULT_SHADOW_KERNEL

TARGETS = ("direct", "indirect", "received")
BAND_PIXELS = 1 << 16
"""Pixels of one band of the gather (one unit of a time-sliced frame): at 960×540 the
gather runs as 8 bands, none longer than a frame budget on llvmpipe takes."""
EXACT_FILTER = 1e-5
"""Largest weight error of a linear-filtered lookup that counts as exact (float32 weights
err by about 1e-7, a texture unit's 8-bit weights by up to 2e-3)."""
PROBE_SAMPLES = 64


@dataclass
class GatherImages:
    """The gather's ``rgba32f`` targets read back, row 0 at the top."""

    direct: np.ndarray
    indirect: np.ndarray
    received: np.ndarray
    """The LPV flux each pixel's surface receives (rgb)."""

    @property
    def gathered(self) -> np.ndarray:
        """(3,) float64: the flux the visible surfaces receive from the LPV, summed over
        the pixels (``Pipeline.gathered_flux``)."""
        return rgb_sums(self.received)


@dataclass(frozen=True)
class Glossy:
    """The glossy reflection's parameters (docs/MODEL.md "Glossy reflections"; the
    ``glossy_*`` Settings) and the eye it reflects."""

    roughness: float
    strength: float
    """k_s, the specular reflectance."""
    samples: int
    eye: tuple[float, float, float]

    def uniforms(self) -> dict[str, object]:
        return {"u_glossy": 1, "u_glossy_g": 1.0 - self.roughness,
                "u_glossy_strength": self.strength, "u_glossy_samples": self.samples,
                "u_camera_position": self.eye}


@dataclass(frozen=True)
class GatherInputs:
    """The gather's switches beyond its textures (the ``gather`` stage's ``Params`` makes
    them from the Settings)."""

    damping: bool = False
    """The directional-derivative damping of the indirect irradiance (docs/MODEL.md
    "Final gather"); with cascades, per cascade."""
    net_flux: bool = False
    """The net-flux gather (docs/MODEL.md "Net-flux gather"): −⟨n, F⟩ + a·E_direct instead
    of the cosine lobe; a single grid only."""
    shadow_kernel: int = DEFAULT_SHADOW_KERNEL
    """Width of the PCF box in shadow-map texels (1 = one hard test)."""
    glossy: Glossy | None = None
    """The glossy reflection of the grid added to the indirect radiance (None: off)."""
    switches: tuple[tuple[str, int], ...] = tuple(
        (name, 1) for name in uniforms_read_by("gather"))
    """The correction switches the gather reads (uniform, 0 or 1), all corrected by
    default."""


NO_GLOSSY = {"u_glossy": 0, "u_glossy_g": 0.0, "u_glossy_strength": 0.0,
             "u_glossy_samples": 0, "u_camera_position": (0.0, 0.0, 0.0)}
"""glossy.glsl's uniforms with the glossy term off."""

NO_GRID_SPEC = GridSpec(origin=(0.0, 0.0, 0.0), cell_size=1.0, resolution=1)
"""The grid uniforms of a gather without a grid (direct light only, ``u_has_grid`` 0): the
program still declares them, and strict uniforms want every one set."""


def program_defines(sh_order: int, shader_filter: bool = False, cascades: bool = False,
                    damping: bool = False, net_flux: bool = False) -> dict[str, object]:
    """The defines ``shaders/gather.glsl`` is compiled with: the SH order, the grid
    lookup's interpolation, whether several cascades are blended and whether the
    derivative damping and the net-flux gather apply (code paths, chosen at compile time:
    the shader says why)."""
    return {**sh_defines(sh_order), "SH_SHADER_FILTER": int(shader_filter),
            "GATHER_CASCADES": int(cascades), "GATHER_DAMPING": int(damping),
            "GATHER_NET_FLUX": int(net_flux)}


def bands(size: tuple[int, int], band_pixels: int = BAND_PIXELS) -> list[tuple[int, int]]:
    """Row ranges ``(first, end)`` covering an image of ``size`` (width, height) in bands
    of about ``band_pixels`` pixels each (at least one row)."""
    width, height = int(size[0]), int(size[1])
    count = max(1, min(height, -(-width * height // band_pixels)))
    edges = [round(i * height / count) for i in range(count + 1)]
    return [(edges[i], edges[i + 1]) for i in range(count)]


def reduced_size(size: tuple[int, int], scale: float) -> tuple[int, int]:
    """``size`` (width, height) times ``scale``, each edge at least one pixel."""
    return (max(1, int(round(size[0] * scale))), max(1, int(round(size[1] * scale))))


def linear_filter_error(ctx: moderngl.Context) -> float:
    """The largest weight error of the texture unit's linear filter (``filter_probe.glsl``),
    measured once per context: interpolating 0 and 1 at fractions t must give t."""
    return per_context(ctx, "linear-filter-error", lambda: _measure_filter_error(ctx))


def _measure_filter_error(ctx: moderngl.Context) -> float:
    import numpy as np

    programs = ProgramCache(ctx)
    ramp = ctx.texture3d((2, 1, 1), 4, np.array([[0.0] * 4, [1.0] * 4], "f4").tobytes(),
                         dtype="f4")
    ramp.filter = (moderngl.LINEAR, moderngl.LINEAR)
    ramp.repeat_x = ramp.repeat_y = ramp.repeat_z = False
    samples = ctx.buffer(reserve=4 * PROBE_SAMPLES)
    try:
        program = programs.get("filter_probe.glsl")
        ramp.use(0)
        samples.bind_to_storage_buffer(0)
        set_uniforms(program, {"u_ramp": 0, "u_count": PROBE_SAMPLES})
        program.run(-(-PROBE_SAMPLES // 64))
        ctx.finish()
        got = np.frombuffer(samples.read(), "f4").astype(np.float64)
    finally:
        samples.release()
        ramp.release()
        programs.release()
    expected = (np.arange(PROBE_SAMPLES) + 0.37) / PROBE_SAMPLES
    return float(np.abs(got - expected).max())


class GatherPass:
    """Full-screen pass writing the ``rgba32f`` targets named in :data:`TARGETS`: linear
    direct and indirect radiance and the LPV flux each pixel's surface receives."""

    STAGE = "gather"
    """Its program reads this stage's correction switches (``GatherInputs.switches``)."""

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self._targets = RenderTargets(ctx, ("f4",) * len(TARGETS))
        self._triangle = FullscreenTriangle(ctx)
        self._empty_grid: moderngl.Texture3D | None = None
        self._lights = LightRecordBuffer(ctx)
        self._uniforms: dict[int, tuple[tuple, dict[str, object]]] = {}
        """Per program (by id: a program the cache recompiles has another): what its
        uniforms were made of and the dict made (never changed once made)."""
        self.shader_filter = linear_filter_error(ctx) > EXACT_FILTER
        """Interpolate the grid in the shader (``SH_SHADER_FILTER``, sh_grid.glsl) because
        the texture unit's weights are not exact on this GPU."""

    @property
    def size(self) -> tuple[int, int]:
        return self._targets.size

    @property
    def targets(self) -> dict[str, moderngl.Texture]:
        """Target name -> texture (empty before the first run)."""
        return dict(zip(TARGETS, self._targets.textures))

    def run(self, gbuffer: GBufferPass, shadow: ShadowMaps, grid: SampledGrid | None,
            params: GatherInputs = GatherInputs(), *,
            rows: tuple[int, int] | None = None, size: tuple[int, int] | None = None
            ) -> None:
        """``shadow``: the RSM views that light the pixels, with their shadow maps.
        ``grid``: the accumulated grid of every cascade (:class:`SampledGrid`, finest
        first, docs/MODEL.md "Cascades"; its textures interpolated trilinearly, clamped
        to the edge), or None for direct light only. ``params``: what the Settings ask of
        the gather (:class:`GatherInputs`: damping, PCF kernel, glossy term). ``rows``:
        gather only these rows (``(first, end)``, GL order; see :func:`bands`), the others
        keep what they hold. ``size``: the targets' size (default the G-buffer's); a
        smaller one gathers a reduced picture, each pixel at the G-buffer texel below it
        (:func:`reduced_size`; the window's quick previews)."""
        self._targets.allocate(size or gbuffer.size)
        several = grid is not None and len(grid.cascades) > 1
        program = self.programs.get("gather.glsl", program_defines(
            grid.sh_order if grid else 1, self.shader_filter, cascades=several,
            damping=params.damping, net_flux=params.net_flux and not several))
        gbuffer.position.use(0)
        gbuffer.normal.use(1)
        gbuffer.albedo.use(2)
        shadow.textures.position.use(3)
        shadow.textures.normal.use(4)
        finest = grid.finest if grid else CascadeInput(NO_GRID_SPEC, (self._empty(),) * 3)
        for unit, texture in enumerate(finest.textures, start=5):
            texture.use(unit)
        light_count = self._lights.bind(shadow.views, shadow.tiles)
        # the uniforms are made again only when what they are made of changes (a moved
        # camera changes none of it): set_uniforms then finds the same dict and skips it
        key = (light_count, params, grid is None, self._targets.size, finest.spec,
               None if grid is None else tuple(level.spec for level in grid.cascades))
        made = self._uniforms.get(id(program))
        if made is None or made[0] != key:
            values = {
                "u_gbuffer_position": 0, "u_gbuffer_normal": 1, "u_gbuffer_albedo": 2,
                "u_shadow_position": 3, "u_shadow_normal": 4,
                "u_lpv_r": 5, "u_lpv_g": 6, "u_lpv_b": 7,
                "u_light_count": light_count,
                "u_shadow_kernel": int(params.shadow_kernel),
                "u_has_grid": int(grid is not None),
                "u_target_size": self._targets.size,
                **finest.spec.uniforms(),
                **self._cascade_uniforms(grid, finest.spec),
                **(NO_GLOSSY if params.glossy is None else params.glossy.uniforms()),
                **dict(params.switches),
            }
            made = self._uniforms[id(program)] = (key, values)
        elif several:
            # cascade_uniforms bound the cascades' textures when it made the dict: the
            # units have held others since (a kept dict bound nothing: a cascaded frame
            # after another frame gathered from whatever those were)
            bind_cascades(grid.cascades, self.CASCADE_FIRST_UNIT)
        set_uniforms(program, made[1], reads=uniforms_read_by(self.STAGE))
        with self._targets.drawing(rows=rows):
            self._triangle.draw(program)

    CASCADE_FIRST_UNIT = 8

    @classmethod
    def _cascade_uniforms(cls, grid: SampledGrid | None, spec: GridSpec) -> dict[str, object]:
        """``cascades.glsl`` uniforms. With a single grid (or none) its sampler arrays point
        at the single grid's units 5..7 (a sampler3D may not share a unit with the
        G-buffer's 2D samplers, even unused) and the count is 1, which selects the
        single-grid code."""
        if grid is None or len(grid.cascades) <= 1:
            return cascade_uniforms([CascadeInput(spec, ())], 5)
        return cascade_uniforms(list(grid.cascades), cls.CASCADE_FIRST_UNIT)

    def _empty(self) -> moderngl.Texture3D:
        if self._empty_grid is None:
            self._empty_grid = self.ctx.texture3d((1, 1, 1), 4, dtype="f4")
        return self._empty_grid

    def release(self) -> None:
        self._targets.release()
        self._triangle.release()
        if self._empty_grid is not None:
            self._empty_grid.release()
            self._empty_grid = None
        self._lights.release()
