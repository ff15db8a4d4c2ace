"""The LPV frame: RSM -> downsample -> inject (+ geometry volume) -> propagate -> gather.

:class:`Pipeline` owns the pass objects and their GPU resources, runs only the stages whose
inputs changed since the last run (each stage has a key made of the Settings fields it
reads plus the keys of the stages it depends on), times every pass, audits the energy and
reads every intermediate result back as numpy arrays (:class:`FrameResult`).

Stages and the Settings fields they read:

========== ==================================================================
scene      scene, camera, light, light_flux, spot_cone, spot_cone_degrees (loads the mesh
           once per scene name)
rsm        scene, light, light_flux, spot_cone, spot_cone_degrees, rsm_size
downsample (rsm, grid) downsample, downsample_factor
inject     (downsample, grid) corrections, injection_mode, grid_format,
           injection_offset_cells, sh_order
geometry   (downsample, grid) corrections, geometry_volume, grid_format
propagate  (inject, geometry) corrections, iterations, bounces (+ keep_steps)
gbuffer    scene, camera, width, height
gather     (gbuffer, rsm, propagate) exposure, indirect_only, gather_damping,
           shadow_kernel
display    (gather) tone_map, auto_exposure (+ display_scale_override)
========== ==================================================================

``grid`` is the :class:`GridSpec` enclosing the scene's bounds at ``grid_size``; with
``cascades`` > 1 it is the list of cascade specs (docs/MODEL.md "Cascades"), which also
depends on the camera (through the snapped focus point) and on ``cascade_extent`` and
``cascade_focus``. The inject, geometry and propagate stages then run every cascade
(their timings hold all cascades together) and the gather blends them.

Timings: on a GPU every pass is timed with a GL timer query (``ctx.query(time=True)``).
Mesa's llvmpipe reads 0 around compute dispatches and, around draws, either 2³²−1 (no
result) or a few microseconds of command submission (it rasterises on worker threads
later), so on a software renderer every pass is timed with the wall clock between two
``ctx.finish()`` calls. A query that reads 0 or 2³²−1 falls back to the wall clock too.
``Pipeline.timing_methods`` records which method timed each pass.
"""

from __future__ import annotations

import hashlib
import time
from dataclasses import dataclass, field

import moderngl
import numpy as np

from explorer.gl.program import ProgramCache
from explorer.lpv.audit import EnergyAudit, GridAudit, check_finite
from explorer.lpv.cascades import (
    DEFAULT_TEXTURE_BUDGET,
    CascadeInput,
    CascadeLevel,
    cascade_iterations,
    cascade_specs,
    focus_point,
)
from explorer.lpv.cascades import check_limits as check_cascade_limits
from explorer.lpv.display import DisplayPass, display_scale
from explorer.lpv.downsample import DownsamplePass
from explorer.lpv.gather import GatherPass
from explorer.lpv.gbuffer import GBufferPass
from explorer.lpv.geometry import GeometryPass, GeometryVolume
from explorer.lpv.grid import GridSpec
from explorer.lpv.inject import InjectPass
from explorer.lpv.propagate import PropagatePass
from explorer.lpv.rsm import LightView, RsmPass, light_view, read_texture
from explorer.lpv.settings import VIEWS, Settings
from explorer.lpv.textures import LpvGrid
from explorer.lpv.views import render_view
from explorer.lpv.vpl import VplArrays, VplTextures
from explorer.scene import Scene, load_scene
from explorer.scene.gpu import SceneBuffers

STAGES = ("scene", "rsm", "downsample", "inject", "geometry", "propagate", "gbuffer", "gather",
          "display")
PASSES = ("rsm", "downsample", "inject", "geometry", "propagate", "gbuffer", "gather",
          "display")
_QUERY_UNAVAILABLE_MS = (2**32 - 1) / 1e6
"""A timer query that reads 2³²−1 ns has no result (Mesa answers so on first use)."""


@dataclass
class FrameResult:
    """Everything one frame computed, as numpy arrays. Images are ``(H, W, 3)`` float32
    with row 0 at the top; RSM arrays ``(Hr, Wr, 4)``, row 0 at the top."""

    settings: Settings
    grid_spec: GridSpec
    final_image: np.ndarray
    """Linear colour, exposure applied (``exposure·indirect`` when ``indirect_only``)."""
    direct: np.ndarray
    """Linear direct radiance (no exposure)."""
    indirect: np.ndarray
    """Linear LPV radiance albedo/π·E (no exposure)."""
    albedo: np.ndarray
    rsm_position: np.ndarray
    rsm_normal: np.ndarray
    rsm_flux: np.ndarray
    vpls: VplArrays
    """The VPLs injected (after downsampling, or the ones handed to :meth:`Pipeline.run`)."""
    accumulated: np.ndarray
    """acc_N, ``(3, N, N, N, 4)`` (L1) or ``(3, N, N, N, 9)`` (``sh_order`` 2)."""
    steps: list[np.ndarray] | None
    geometry_volume: np.ndarray | None
    audit: EnergyAudit
    timings_ms: dict[str, float]
    """Pass name -> milliseconds of its last run (also for passes skipped this time)."""
    timing_methods: dict[str, str] = field(default_factory=dict)
    """Pass name -> "timer-query" or "wall-clock"."""
    stages_run: tuple[str, ...] = ()
    """The stages that ran for this result (the others were up to date)."""
    # Cascades (docs/MODEL.md "Cascades"): the fields above without a cascade index
    # (grid_spec, accumulated, steps, geometry_volume, audit's grid terms) are cascade 0's,
    # the finest; the lists below hold every cascade, finest first (one entry when
    # settings.cascades == 1). audit.gathered is the blended final gather's.
    cascade_specs: list[GridSpec] = field(default_factory=list)
    """GridSpec of each cascade; [grid_spec] for the single grid."""
    cascade_accumulated: list[np.ndarray] = field(default_factory=list)
    """acc_N of each cascade, ``(3, N, N, N, 4)`` (or ``9`` coefficients with L2)."""
    cascade_geometry: list[np.ndarray | None] = field(default_factory=list)
    """Geometry volume of each cascade (None when off)."""
    cascade_audits: list[GridAudit] = field(default_factory=list)
    """Injection and propagation audit of each cascade. Each cascade holds every VPL
    inside it, so their injected fluxes overlap and must not be summed."""
    display_scale: float = 1.0
    """What the display multiplies ``final_image`` by before the tone curve
    (docs/MODEL.md "Display"): the auto exposure key/L̄, 1 without it, or
    ``Pipeline.display_scale_override``. ``render_view("final")`` and the display texture
    both use it."""


class Pipeline:
    """Orders the passes of one LPV frame and keeps their results between runs."""

    def __init__(self, settings: Settings, ctx: moderngl.Context | None = None) -> None:
        if ctx is None:
            from explorer.gl.context import create_headless_context

            ctx = create_headless_context()
            self._owns_context = True
        else:
            self._owns_context = False
        self.ctx = ctx
        self.settings = settings
        self.programs = ProgramCache(ctx)
        info = ctx.info
        self.max_3d_texture_size = int(info.get("GL_MAX_3D_TEXTURE_SIZE", 0) or 0)
        self.max_texture_size = int(info.get("GL_MAX_TEXTURE_SIZE", 0) or 0)
        self.max_texture_units = int(info.get("GL_MAX_TEXTURE_IMAGE_UNITS", 0) or 0)
        self.texture_budget_bytes = DEFAULT_TEXTURE_BUDGET
        """Refuse settings whose LPV textures (all cascades) would need more bytes."""
        renderer = str(info.get("GL_RENDERER", "")).lower()
        self.software_renderer = any(name in renderer for name in ("llvmpipe", "softpipe",
                                                                   "swrast", "lavapipe"))
        self._rsm = RsmPass(ctx, self.programs)
        self._downsample = DownsamplePass(ctx, self.programs)
        self._inject = InjectPass(ctx, self.programs)
        self._geometry = GeometryPass(ctx, self.programs)
        self._propagate = PropagatePass(ctx, self.programs)
        self._gbuffer = GBufferPass(ctx, self.programs)
        self._gather = GatherPass(ctx, self.programs)
        self._display = DisplayPass(ctx, self.programs)
        self.display_scale_override: float | None = None
        """Show the frame with this display scale instead of its own (the window shows
        configuration B at A's exposure); None = the frame's own (auto exposure or 1)."""
        self._display_scale = 1.0
        self._keys: dict[str, object] = {}
        self._scene_cache: dict[str, Scene] = {}
        self._scene: Scene | None = None
        self._geometry_buffers: SceneBuffers | None = None
        self._light: LightView | None = None
        self._spec: GridSpec | None = None
        self._rsm_textures: VplTextures | None = None
        self._vpl_textures: VplTextures | None = None
        self._override_textures: VplTextures | None = None
        self._injected: LpvGrid | None = None
        self._volume: GeometryVolume | None = None
        self._accumulated_grid: LpvGrid | None = None
        self._arrays: dict[str, object] = {}
        self._grid_audit: GridAudit | None = None
        self._specs: list[GridSpec] = []
        self._levels: list[CascadeLevel] = []     # cascades 1.. (cascade 0: the above)
        self.timings_ms: dict[str, float] = {}
        self.timing_methods: dict[str, str] = {}
        self._queries: dict[str, moderngl.Query] = {}
        self._current_stage: str | None = None
        self.last_result: FrameResult | None = None

    # ------------------------------------------------------------------ public API
    @property
    def final_texture(self) -> moderngl.Texture:
        """RGBA8 final image of the last run as shown (display scale, tone curve, sRGB;
        docs/MODEL.md "Display"). Row 0 is the bottom row, as OpenGL draws it."""
        if self._display.texture is None:
            raise RuntimeError("the pipeline has not run yet: call run() first")
        return self._display.texture

    def run(self, settings: Settings | None = None, keep_steps: bool = False,
            vpls: VplArrays | None = None) -> FrameResult:
        """Render a frame; only the stages whose inputs changed run again.

        ``vpls``: inject these VPLs instead of the RSM's (the RSM still renders for the
        direct light and its shadow); lessons and tests use it for hand-made light.
        """
        if settings is not None:
            self.settings = settings
        self._check_limits(self.settings)
        self._current_stage = None
        try:
            return self._run(self.settings, keep_steps, vpls)
        except BaseException:
            # the failed stage (and all after it) must run again next time
            self.invalidate(self._current_stage or "scene")
            raise

    def _run(self, s: Settings, keep_steps: bool, vpls: VplArrays | None) -> FrameResult:
        ran: list[str] = []

        scene_key = (s.scene, s.camera, s.light, s.light_flux, s.spot_cone, s.spot_cone_degrees)
        if self._changed("scene", scene_key):
            self._load_scene(s)
            ran.append("scene")
        scene = self._scene
        specs = self._cascade_specs(s, scene)
        spec = specs[0]
        self._spec = spec

        # the camera does not change what the light sees: moving it re-runs only the
        # G-buffer and the gather
        light_key = (s.scene, s.light, s.light_flux, s.spot_cone, s.spot_cone_degrees)
        rsm_key = (light_key, s.rsm_size)
        if self._changed("rsm", rsm_key):
            self._light = light_view(scene, s.rsm_size)
            self._rsm_textures = self._timed(
                "rsm", lambda: self._rsm.run(self._geometry_buffers, self._light))
            self._arrays["rsm"] = tuple(read_texture(t) for t in (
                self._rsm_textures.position, self._rsm_textures.normal,
                self._rsm_textures.flux))
            for array in self._arrays["rsm"]:
                self._check("rsm", array)
            ran.append("rsm")

        override_key = None if vpls is None else _digest(vpls)
        downsample_key = (rsm_key, spec, s.downsample, s.downsample_factor, override_key)
        if self._changed("downsample", downsample_key):
            self._vpl_textures = self._select_vpls(s, spec, vpls)
            self._arrays["vpls"] = self._vpl_textures.to_arrays()
            if vpls is None:   # hand-made VPLs are the caller's: a NaN shows up at inject
                self._check("downsample", self._arrays["vpls"].flux)
            ran.append("downsample")

        inject_key = (downsample_key, s.corrections, s.injection_mode, s.grid_format,
                      s.injection_offset_cells, tuple(specs), s.sh_order)
        if self._changed("inject", inject_key):
            self._injected = self._replace_grid(self._injected, s)

            def inject_all() -> None:   # cascade 0, then the coarser cascades
                self._inject.run(self._vpl_textures, spec, s.corrections, s.injection_mode,
                                 self._injected, s.injection_offset_cells)
                self._inject_cascades(s, specs)

            self._timed("inject", inject_all)
            if s.debug_nan:
                self._check("inject", self._injected.read())
            ran.append("inject")

        geometry_key = (downsample_key, s.corrections, s.geometry_volume, s.grid_format,
                        tuple(specs))
        if self._changed("geometry", geometry_key):
            occluders = self._rsm_textures if vpls is None else self._vpl_textures
            if s.geometry_volume == "off":
                self.timings_ms.pop("geometry", None)
                self._release_volume()
                self._arrays["geometry"] = None
                for level in self._levels:
                    level.release_volume()
            else:
                if self._volume is None or self._volume.resolution != spec.resolution or \
                        self._volume.format != s.grid_format:
                    self._release_volume()
                    self._volume = GeometryVolume(self.ctx, spec.resolution, s.grid_format)

                def geometry_all() -> None:   # cascade 0, then the coarser cascades
                    self._geometry.run(occluders, spec, s.corrections, s.geometry_volume,
                                       self._volume)
                    self._geometry_cascades(s, specs, occluders)

                self._timed("geometry", geometry_all)
                self._arrays["geometry"] = self._volume.read()
                self._check("geometry", self._arrays["geometry"])
            ran.append("geometry")

        propagate_key = (inject_key, geometry_key, s.iterations, s.bounces, keep_steps,
                         s.cascade_iterations)
        if self._changed("propagate", propagate_key):

            def propagate_all():   # cascade 0 (returned), then the coarser cascades
                finest = self._propagate.run(self._injected, spec, s.corrections,
                                             cascade_iterations(s, 0), self._volume,
                                             keep_steps=keep_steps, bounces=s.bounces)
                self._propagate_cascades(s, specs)
                return finest

            output = self._timed("propagate", propagate_all)
            self._accumulated_grid = output.accumulated
            self._grid_audit = output.audit
            self._arrays["accumulated"] = output.accumulated.read()
            self._arrays["steps"] = output.steps
            self._check("propagate", self._arrays["accumulated"])
            ran.append("propagate")

        gbuffer_key = (s.scene, s.camera, s.width, s.height)
        if self._changed("gbuffer", gbuffer_key):
            self._timed("gbuffer", lambda: self._gbuffer.run(
                self._geometry_buffers, scene, (s.width, s.height)))
            self._arrays["gbuffer"] = tuple(read_texture(t)
                                            for t in self._gbuffer.textures)
            for array in self._arrays["gbuffer"]:
                self._check("gbuffer", array)
            ran.append("gbuffer")

        gather_key = (gbuffer_key, rsm_key, propagate_key, s.exposure, s.indirect_only,
                      s.gather_damping, s.shadow_kernel)
        if self._changed("gather", gather_key):
            self._timed("gather", lambda: self._gather.run(
                self._gbuffer, self._rsm_textures, self._light,
                self._accumulated_grid.textures, spec, s.exposure, s.indirect_only,
                s.gather_damping, cascades=self._cascade_inputs(specs),
                sh_order=self._accumulated_grid.sh_order, shadow_kernel=s.shadow_kernel))
            targets = self._gather.targets
            self._arrays["gather"] = {name: read_texture(targets[name])
                                      for name in ("direct", "indirect", "final", "received")}
            for array in self._arrays["gather"].values():
                self._check("gather", array)
            ran.append("gather")

        display_key = (gather_key, s.tone_map, s.auto_exposure, self.display_scale_override)
        if self._changed("display", display_key):
            self._display_scale = self._frame_display_scale(s)
            self._timed("display", lambda: self._display.run(
                self._gather.targets["final"], self._display_scale, s.tone_map))
            ran.append("display")

        self.last_result = self._result(s, spec, ran)
        self._add_cascade_results(self.last_result, specs)
        return self.last_result

    def invalidate(self, stage: str | None = None) -> None:
        """Make the next :meth:`run` redo ``stage`` and every stage after it in
        :data:`STAGES` (all stages when None), e.g. to time a whole frame or after editing
        a scene file."""
        if stage is not None and stage not in STAGES:
            raise ValueError(f"unknown stage {stage!r}; stages are {STAGES}")
        first = STAGES.index(stage) if stage is not None else 0
        if first == 0:
            self._scene_cache.clear()
        for name in STAGES[first:]:
            self._keys.pop(name, None)

    def reload_shaders(self) -> bool:
        """Recompile the programs whose ``.glsl`` files changed (a failed compile keeps the
        last good program; ``self.programs.errors`` holds the log). True if any changed:
        then every stage runs again on the next :meth:`run`."""
        changed = self.programs.reload_if_changed()
        if changed:
            self.invalidate("rsm")
        return changed

    def view(self, name: str, **options) -> np.ndarray:
        """The last frame shown as ``name`` (any of ``settings.VIEWS``): an ``(H, W, 3)``
        float32 image in [0, 1], ready for display (sRGB-encoded for radiometric views,
        normalised for data views). See :func:`explorer.lpv.views.render_view` for the
        options."""
        if name not in VIEWS:
            raise ValueError(f"unknown view {name!r}; choose one of {VIEWS}")
        if self.last_result is None:
            self.run()
        scene = self._scene
        if name == "cascade-weights":
            options["positions"] = self._arrays["gbuffer"][0]
        return render_view(self.last_result, name, bounds=(scene.bounds_min, scene.bounds_max),
                           **options)

    def __enter__(self) -> "Pipeline":
        return self

    def __exit__(self, *exc_info) -> None:
        self.release()

    def release(self) -> None:
        for stage in (self._rsm, self._downsample, self._inject, self._geometry,
                      self._propagate, self._gbuffer, self._gather, self._display):
            stage.release()
        for grid in (self._injected,):
            if grid is not None:
                grid.release()
        self._injected = None
        self._release_volume()
        self._release_levels(0)
        if self._override_textures is not None:
            self._override_textures.release()
            self._override_textures = None
        if self._geometry_buffers is not None:
            self._geometry_buffers.release()
            self._geometry_buffers = None
        self.programs.release()
        self._keys.clear()
        if self._owns_context:
            from explorer.gl.context import release_headless_context

            release_headless_context(self.ctx)

    # ------------------------------------------------------------------ stages
    def _changed(self, stage: str, key: object) -> bool:
        if self._keys.get(stage) == key:
            return False
        self._keys[stage] = key
        self._current_stage = stage
        return True

    @property
    def base_scene(self) -> Scene | None:
        """The scene of the last run as loaded, before the Settings' camera, light and
        flux overrides (its own defaults); None before the first run."""
        return self._scene_cache.get(self.settings.scene) if self._scene_cache else None

    def _load_scene(self, s: Settings) -> None:
        base = self._scene_cache.get(s.scene)
        if base is None:
            base = load_scene(s.scene)
            self._scene_cache = {s.scene: base}
            if self._geometry_buffers is not None:
                self._geometry_buffers.release()
            self._geometry_buffers = SceneBuffers(self.ctx, base)
        self._scene = base.for_settings(s)

    def _select_vpls(self, s: Settings, spec: GridSpec, vpls: VplArrays | None
                     ) -> VplTextures:
        if self._override_textures is not None:
            self._override_textures.release()
            self._override_textures = None
        if vpls is not None:
            self.timings_ms.pop("downsample", None)
            self._override_textures = VplTextures.from_arrays(self.ctx, vpls)
            return self._override_textures
        if s.downsample == "none" or s.downsample_factor == 1:
            self.timings_ms.pop("downsample", None)
            return self._rsm_textures
        return self._timed("downsample", lambda: self._downsample.run(
            self._rsm_textures, s.downsample, s.downsample_factor, spec, self._light))

    def _replace_grid(self, grid: LpvGrid | None, s: Settings) -> LpvGrid:
        if grid is not None and grid.resolution == s.grid_size and \
                grid.format == s.grid_format and grid.sh_order == s.sh_order:
            return grid
        if grid is not None:
            grid.release()
        return LpvGrid(self.ctx, s.grid_size, s.grid_format, s.sh_order)

    def _release_volume(self) -> None:
        if self._volume is not None:
            self._volume.release()
            self._volume = None

    def _check_limits(self, s: Settings) -> None:
        if self.max_3d_texture_size and s.grid_size > self.max_3d_texture_size:
            raise ValueError(f"grid_size {s.grid_size} exceeds this driver's "
                             f"GL_MAX_3D_TEXTURE_SIZE {self.max_3d_texture_size}")
        # L2 stacks its 3 texel groups along z (explorer/lpv/textures.py)
        if s.sh_order == 2 and self.max_3d_texture_size and \
                3 * s.grid_size > self.max_3d_texture_size:
            raise ValueError(f"sh_order 2 stores 3·grid_size = {3 * s.grid_size} texels "
                             f"along z, more than this driver's GL_MAX_3D_TEXTURE_SIZE "
                             f"{self.max_3d_texture_size}")
        for name in ("rsm_size", "width", "height"):
            value = int(getattr(s, name))
            if value < 1:
                raise ValueError(f"{name} must be at least 1, got {value}")
            if self.max_texture_size and value > self.max_texture_size:
                raise ValueError(f"{name} {value} exceeds this driver's GL_MAX_TEXTURE_SIZE "
                                 f"{self.max_texture_size}")
        check_cascade_limits(s.grid_size, s.cascades, s.grid_format,
                             s.geometry_volume != "off", self.texture_budget_bytes,
                             self.max_texture_units, sh_groups=3 if s.sh_order == 2 else 1)

    def _check(self, pass_name: str, array) -> None:
        """With ``settings.debug_nan``: a FloatingPointError naming ``pass_name`` if its
        output holds NaN or infinity."""
        if self.settings.debug_nan:
            check_finite(np.asarray(array), f"the {pass_name} pass")

    def _timed(self, name: str, work):
        """Run ``work()`` and record its GPU time in milliseconds (module docstring)."""
        use_clock = self.software_renderer
        self.ctx.finish()
        start = time.perf_counter()
        query = None
        if not use_clock:   # one query object per pass, reused (moderngl cannot free them)
            query = self._queries.get(name)
            if query is None:
                query = self._queries[name] = self.ctx.query(time=True)
        if query is None:
            result = work()
        else:
            with query:
                result = work()
        self.ctx.finish()
        wall_ms = (time.perf_counter() - start) * 1e3
        query_ms = 0.0 if query is None else query.elapsed / 1e6
        if 0.0 < query_ms < _QUERY_UNAVAILABLE_MS:
            self.timings_ms[name], self.timing_methods[name] = query_ms, "timer-query"
        else:
            self.timings_ms[name], self.timing_methods[name] = wall_ms, "wall-clock"
        return result

    # ------------------------------------------------------------------ cascades
    # docs/MODEL.md "Cascades". Cascade 0 runs through the single-grid code above
    # (self._injected, self._volume, self._propagate); cascades 1.. live in self._levels
    # and run through the same pass objects (inject, geometry) or their own
    # PropagatePass.
    def _cascade_specs(self, s: Settings, scene: Scene) -> list[GridSpec]:
        single = GridSpec.enclosing(scene.bounds_min, scene.bounds_max, s.grid_size)
        if s.cascades == 1:
            specs = [single]
        else:
            camera = scene.camera
            centre = focus_point(camera.eye, camera.target, s.cascade_focus)
            specs = cascade_specs(single, s.cascades, centre, s.cascade_extent)
        self._specs = specs
        return specs

    def _release_levels(self, keep: int) -> None:
        """Free the cascade levels beyond the first ``keep``."""
        for level in self._levels[keep:]:
            level.release()
        del self._levels[keep:]

    def _cascade_levels(self, specs: list[GridSpec]) -> list[CascadeLevel]:
        self._release_levels(len(specs) - 1)
        while len(self._levels) < len(specs) - 1:
            self._levels.append(CascadeLevel(self.ctx, self.programs))
        return self._levels

    def _inject_cascades(self, s: Settings, specs: list[GridSpec]) -> None:
        """Every VPL into every coarser cascade (injection drops those outside a grid)."""
        for level, spec in zip(self._cascade_levels(specs), specs[1:]):
            self._inject.run(self._vpl_textures, spec, s.corrections, s.injection_mode,
                             level.grid(spec.resolution, s.grid_format, s.sh_order),
                             s.injection_offset_cells)

    def _geometry_cascades(self, s: Settings, specs: list[GridSpec], occluders) -> None:
        for level, spec in zip(self._cascade_levels(specs), specs[1:]):
            volume = level.geometry_volume(spec.resolution, s.grid_format)
            self._geometry.run(occluders, spec, s.corrections, s.geometry_volume, volume)
            level.geometry = volume.read()
            self._check("geometry", level.geometry)

    def _propagate_cascades(self, s: Settings, specs: list[GridSpec]) -> None:
        """``cascade_iterations(s, k)`` steps in cascade k (the same count in every cascade
        by default: light then travels 2^k cells of the finest cascade per step)."""
        for k, (level, spec) in enumerate(zip(self._cascade_levels(specs), specs[1:]), 1):
            level.output = level.propagate.run(level.injected, spec, s.corrections,
                                               cascade_iterations(s, k), level.volume,
                                               bounces=s.bounces)
            level.accumulated = level.output.accumulated.read()
            self._check("propagate", level.accumulated)

    def _cascade_inputs(self, specs: list[GridSpec]) -> list[CascadeInput] | None:
        if len(specs) == 1:
            return None
        inputs = [CascadeInput(specs[0], self._accumulated_grid.textures)]
        inputs += [CascadeInput(spec, level.output.accumulated.textures)
                   for level, spec in zip(self._levels, specs[1:])]
        return inputs

    def _add_cascade_results(self, result: FrameResult, specs: list[GridSpec]) -> None:
        levels = self._levels[: len(specs) - 1]
        result.cascade_specs = list(specs)
        result.cascade_accumulated = [result.accumulated] + [lv.accumulated for lv in levels]
        result.cascade_geometry = [result.geometry_volume] + [lv.geometry for lv in levels]
        result.cascade_audits = [self._grid_audit] + [lv.output.audit for lv in levels]

    # ------------------------------------------------------------------ results
    def _frame_display_scale(self, s: Settings) -> float:
        """The display scale of the frame just gathered: the override, or the auto
        exposure of its unexposed image over the pixels that show a surface."""
        if self.display_scale_override is not None:
            return float(self.display_scale_override)
        if not s.auto_exposure:
            return 1.0
        gather = self._arrays["gather"]
        unexposed = gather["indirect"][..., :3]
        if not s.indirect_only:
            unexposed = unexposed + gather["direct"][..., :3]
        return display_scale(unexposed, self._arrays["gbuffer"][0][..., 3] > 0.5, True)

    def gathered_flux(self) -> np.ndarray:
        """(3,) flux [W] the visible surfaces receive from the LPV: the sum over pixels of
        the indirect irradiance E (docs/MODEL.md "Final gather") times the world area of
        the surface under the pixel (|∂p/∂x × ∂p/∂y| from the G-buffer). Only surfaces the
        camera sees count, once per pixel, so it is not expected to equal the injected
        flux: it says how much LPV light lands on what is on screen."""
        received = self._arrays["gather"]["received"]
        return received[..., :3].astype(np.float64).sum(axis=(0, 1))

    def _result(self, s: Settings, spec: GridSpec, ran: list[str]) -> FrameResult:
        rsm_position, rsm_normal, rsm_flux = self._arrays["rsm"]
        position, normal, albedo = self._arrays["gbuffer"]
        gather = self._arrays["gather"]
        rsm_total = rsm_flux[..., :3].astype(np.float64).sum(axis=(0, 1))
        audit = EnergyAudit.from_grid_audit(self._grid_audit, rsm=rsm_total,
                                            gathered=self.gathered_flux())
        return FrameResult(
            settings=s, grid_spec=spec,
            final_image=gather["final"][..., :3], direct=gather["direct"][..., :3],
            indirect=gather["indirect"][..., :3], albedo=albedo[..., :3],
            rsm_position=rsm_position, rsm_normal=rsm_normal, rsm_flux=rsm_flux,
            vpls=self._arrays["vpls"], accumulated=self._arrays["accumulated"],
            steps=self._arrays["steps"], geometry_volume=self._arrays["geometry"],
            audit=audit, timings_ms=dict(self.timings_ms),
            timing_methods=dict(self.timing_methods), stages_run=tuple(ran),
            display_scale=self._display_scale)


def render(settings: Settings) -> FrameResult:
    """One frame with a throw-away headless pipeline (scripts, notebooks)."""
    with Pipeline(settings) as pipeline:
        return pipeline.run()


def _digest(vpls: VplArrays) -> str:
    """Content hash of hand-made VPLs, so the same arrays do not re-run injection."""
    digest = hashlib.sha1()
    arrays = [vpls.positions, vpls.normals, vpls.flux, vpls.depth]
    if vpls.albedo is not None:
        arrays.append(vpls.albedo)
    for array in arrays:
        digest.update(np.ascontiguousarray(array, np.float32).tobytes())
    digest.update(repr((vpls.texel_area, vpls.projection)).encode())
    return digest.hexdigest()
