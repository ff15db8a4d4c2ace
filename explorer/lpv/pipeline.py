"""The LPV frame: RSM -> downsample -> inject (+ geometry volume) -> propagate -> gather ->
fog -> display.

:class:`Pipeline` owns the pass objects and their GPU resources and runs the stages
declared in :mod:`explorer.lpv.stages` (their table: ``stages.describe()``). A stage runs
only when its key changed: the Settings fields it reads (declared once, in the settings
schema), the output keys of its upstream stages and its extra inputs. Every stage is
timed, its output is checked for NaN and infinity (warnings in ``FrameResult.warnings``,
or a FloatingPointError with ``debug_nan``), and what ``FrameResult`` holds is read
back when the stage runs.

Two ways to run a frame:

* :meth:`Pipeline.run`: the whole frame at once (scripts, the CLI, tests), with the
  energy audit by default and a ``progress(stage, done, total)`` callback;
* :meth:`Pipeline.start`: a :class:`~explorer.lpv.job.Job` that the window advances a
  few milliseconds per frame (``job.advance(budget_ms)``), showing the accumulation grow
  (``job.preview()``) and cancelled by the next ``start`` with other settings.

Several lights (docs/MODEL.md "Several lights"): :attr:`Pipeline.light_views`
(explorer/lpv/light_views.py) renders one RSM per view of every light that shines and
puts the views side by side for the injection; the geometry volume merges the views'
volumes per cell, the gather and the fog sum every view's direct light with its own
shadow map, and camera occluders keep the G-buffer pixels no view's shadow map holds
(docs/MODEL.md "Fog", "Camera occluders").

Moving objects (``Settings.object_transforms``) are posed by the ``scene`` stage
(:attr:`Pipeline.scene_state`, explorer/lpv/scene_state.py), which rewrites only their
corners in the vertex buffer; the stages downstream of it then run again by their keys.

Cascades (docs/MODEL.md "Cascades") are a list of levels, level 0 the finest (or the
single grid enclosing the scene); inject, geometry and propagate run every level (their
timings hold all levels together) and the gather blends them.

Timings: every pass is timed by :class:`~explorer.lpv.timing.PassTimer` (a GL timer
query, or the wall clock on a software renderer), in ``FrameResult.timings_ms``.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable, Iterator

import moderngl
import numpy as np

from explorer.gl.program import ProgramCache
from explorer.lpv import guards
from explorer.lpv import fog as fog_pass
from explorer.lpv import gather as gather_pass
from explorer.lpv import gbuffer as gbuffer_pass
from explorer.lpv.audit import audit_covers, check_finite
from explorer.lpv.cascades import (
    CascadeInput,
    CascadeLevel,
    cascade_iterations,
    frame_specs,
    level_pass_name,
)
from explorer.lpv.cascades import check_limits as check_cascade_limits
from explorer.lpv.display import AutoExposure, DisplayPass, FogImages
from explorer.lpv.fog import FogPass, Medium
from explorer.lpv.frame import FrameResult, LevelResult, frame_result
from explorer.lpv.gather import GatherPass, Glossy, bands, reduced_size
from explorer.lpv.gbuffer import GBufferPass
from explorer.lpv.geometry import CameraSurfels, MergedGeometryPass, camera_pixel_area
from explorer.lpv.grid import GridSpec
from explorer.lpv.inject import InjectPass
from explorer.lpv.job import Job, ProgressCallback
from explorer.lpv.limits import (
    DEFAULT_MEMORY_BUDGET,
    DriverLimits,
    audit_fits,
    audit_skipped_warning,
    check_framebuffers,
    check_grid_textures,
    check_memory,
)
from explorer.lpv.propagate import read_in_units, slabs
from explorer.lpv.light_views import LightViews
from explorer.lpv.scene_state import SceneState
from explorer.lpv.schema import STAGES
from explorer.lpv.settings import VIEWS, Settings
from explorer.lpv.views import render_view
from explorer.lpv.timing import PassTimer
from explorer.lpv.vpl import VplArrays
from explorer.lpv.work_units import countdown, read_back, single_unit
from explorer.scene import Scene

__all__ = ["FrameResult", "LevelResult", "Pipeline", "render"]


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
        self.limits = DriverLimits.of(ctx.info)
        """The GL limits every request is checked against (explorer/lpv/limits.py)."""
        self.memory_budget_bytes = DEFAULT_MEMORY_BUDGET
        """Refuse settings whose textures and read-back arrays would need more bytes."""
        self.timer = PassTimer(ctx)
        """Times every pass (``timings_ms``, ``timing_methods``; explorer/lpv/timing.py)."""
        self.light_views = LightViews(ctx, self.programs, self.timer)
        """The RSM and downsample passes of every light view, their atlases and what the
        ``rsm`` and ``downsample`` stages left (explorer/lpv/light_views.py)."""
        self.scene_state = SceneState(ctx)
        """The loaded and posed scene, its vertex buffer and the frame's scene with the
        Settings applied (explorer/lpv/scene_state.py)."""
        self._inject = InjectPass(ctx, self.programs)
        self._geometry = MergedGeometryPass(ctx, self.programs)
        self._gbuffer = GBufferPass(ctx, self.programs)
        self._gather = GatherPass(ctx, self.programs)
        self._preview_gather: GatherPass | None = None
        """The reduced previews' own targets (made at the first one)."""
        self.preview_textures: tuple | None = None
        """``(direct, indirect, albedo)`` of the last preview (:meth:`show_preview`)."""
        self._fog = FogPass(ctx, self.programs)
        self._display = DisplayPass(ctx, self.programs)
        self.display_scale_override: float | None = None
        """Show frames with this display scale instead of their own (the window shows
        configuration B at A's exposure); None = the frame's own (auto exposure or 1). An
        input of the display stage: changing it runs that stage alone."""
        self._display_scale = 1.0
        self._auto_exposure = AutoExposure()
        self.keys: dict[str, object] = {}
        """Stage -> key of its last completed run (forgotten while it runs)."""
        self.out_keys: dict[str, object] = {}
        """By-value stage -> its last value (the grid specs)."""
        self.unit_ms: dict[str, float] = {}
        """Stage -> measured milliseconds of its last unit of work (a job's budget)."""
        self.job: Job | None = None
        """The job in progress, if any."""
        self._specs: list[GridSpec] = []
        self._levels: list[CascadeLevel] = []
        self._arrays: dict[str, object] = {}
        self._warnings: dict[str, list[str]] = {}
        """Stage -> the warnings of its last run (explorer/lpv/guards.py)."""
        self.last_result: FrameResult | None = None

    # ------------------------------------------------------------------ public API
    @property
    def timings_ms(self) -> dict[str, float]:
        """Pass name -> milliseconds of its last run (:attr:`timer`'s)."""
        return self.timer.timings_ms

    @property
    def timing_methods(self) -> dict[str, str]:
        """Pass name -> "timer-query" or "wall-clock" (:attr:`timer`'s)."""
        return self.timer.methods

    @property
    def software_renderer(self) -> bool:
        """Whether the context renders in software (e.g. llvmpipe)."""
        return self.timer.software_renderer

    def measure(self, name: str, work: Callable[[], object]) -> tuple[object, float, str]:
        """``(work(), milliseconds, method)``, recording nothing
        (:meth:`explorer.lpv.timing.PassTimer.measure`)."""
        return self.timer.measure(name, work)

    @property
    def final_texture(self) -> moderngl.Texture:
        """RGBA8 final image as shown (exposure, display scale, tone curve, sRGB;
        docs/MODEL.md "Display") of the last frame shown (a finished run, or a job's
        preview). Row 0 is the bottom row, as OpenGL draws it."""
        if self._display.texture is None:
            raise RuntimeError("the pipeline has not run yet: call run() first")
        return self._display.texture

    @property
    def linear_textures(self) -> tuple[moderngl.Texture, moderngl.Texture, moderngl.Texture]:
        """``(direct, indirect, albedo)``: the gather's linear ``rgba32f`` radiance and the
        G-buffer's albedo (w = 1 on a surface), as the last gather or preview left them
        (the window copies them and applies the display itself, explorer/ui/picture.py).
        They are rewritten while a job runs."""
        targets = self._gather.targets
        if not targets or not self._gbuffer.textures:
            raise RuntimeError("the pipeline has not gathered yet: call run() first")
        return targets["direct"], targets["indirect"], self._gbuffer.textures[2]

    @property
    def fog_textures(self) -> tuple[moderngl.Texture, moderngl.Texture] | None:
        """``(fog_direct, fog_lpv)``: the fog pass's ``rgba32f`` targets of the last frame
        (the direct light's in-scattered radiance with the transmittance in w, the LPV's
        in-scattered radiance), which the display composes over :attr:`linear_textures`
        (docs/MODEL.md "Fog"); None when that frame has no fog."""
        if not self.settings.fog or self._arrays.get("fog") is None:
            return None
        targets = self._fog.targets
        return targets["fog_direct"], targets["fog_lpv"]

    def start(self, settings: Settings | None = None, keep_steps: bool = False,
              vpls: VplArrays | None = None, need_audit: str | bool = True,
              progress: ProgressCallback | None = None) -> Job:
        """A :class:`~explorer.lpv.job.Job` for a frame with ``settings`` (default: the
        last ones); the job in progress, if any, is cancelled first. Limits are checked
        here: a request that does not fit raises a one-line ValueError before anything is
        allocated.

        ``keep_steps``: keep grid_0..grid_N of every cascade. ``need_audit``: what the
        energy audit measures (:data:`explorer.lpv.audit.AUDIT_MODES`; True ``full``,
        False ``off``): ``full`` every term (the Energy audit plot, a picked cell, a
        lesson or command quoting them), ``flux`` only the flux in flight per step (the
        flux-per-step plot; the minimal kernel), ``off`` only the injected and
        accumulated flux. A later job that needs more propagates again. ``vpls``:
        inject these VPLs instead of the RSM's (the RSM still renders for the direct
        light and its shadow); lessons and tests use it for hand-made light. Asking again
        for the frame the job in progress makes returns that job, so a caller may start
        every frame."""
        settings = self.settings if settings is None else settings
        current = self.job
        if current is not None and current.asks_for(settings, keep_steps, need_audit, vpls):
            current.progress_callback = progress
            return current           # the same frame: carry on where it is
        if current is not None:
            current.cancel()
        self.settings = settings
        self.check_limits(self.settings)
        self.job = Job(self, self.settings, keep_steps, need_audit, vpls, progress)
        return self.job

    def run(self, settings: Settings | None = None, keep_steps: bool = False,
            vpls: VplArrays | None = None, need_audit: str | bool = True,
            progress: ProgressCallback | None = None) -> FrameResult:
        """Render a frame at once; only the stages whose inputs changed run again.
        ``progress(stage, done, total)`` is called as it goes (see :meth:`start` for the
        other options). An exception, KeyboardInterrupt included, leaves the unfinished
        stage to run again next time and propagates."""
        job = self.start(settings, keep_steps, vpls, need_audit, progress)
        job.advance(None)
        return job.result

    def invalidate(self, stage: str | None = None) -> None:
        """Make the next run redo ``stage`` and every stage after it in
        :data:`~explorer.lpv.schema.STAGES` (all stages when None), e.g. to time a whole
        frame or after editing a scene file."""
        if stage is not None and stage not in STAGES:
            raise ValueError(f"unknown stage {stage!r}; stages are {STAGES}")
        first = STAGES.index(stage) if stage is not None else 0
        if first == 0:
            self.scene_state.forget()
        for name in STAGES[first:]:
            self.keys.pop(name, None)

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
        result = self.last_result
        if name == "cascade-weights":
            options["positions"] = result.gbuffer_position
        scene = self.scene_state.scene
        return render_view(result, name, bounds=(scene.bounds_min, scene.bounds_max),
                           **options)

    @property
    def base_scene(self) -> Scene | None:
        """The scene of the last run as loaded, before the Settings' camera, light and
        flux overrides (its own defaults); None before the first run."""
        return self.scene_state.base(self.settings.scene)

    @property
    def pose_ms(self) -> float:
        """Wall-clock milliseconds the scene stage last spent posing objects
        (:attr:`SceneState.pose_ms`)."""
        return self.scene_state.pose_ms

    def gathered_flux(self) -> np.ndarray:
        """(3,) flux [W] the visible surfaces receive from the LPV: the sum over pixels of
        the indirect irradiance E (docs/MODEL.md "Final gather") times the world area of
        the surface under the pixel (|∂p/∂x × ∂p/∂y| from the G-buffer). Only surfaces the
        camera sees count, once per pixel, so it is not expected to equal the injected
        flux: it says how much LPV light lands on what is on screen."""
        return self._arrays["gathered"].copy()

    def check_limits(self, s: Settings) -> None:
        """A one-line ValueError when ``s`` asks for more than the driver or the memory
        budget allows (explorer/lpv/limits.py)."""
        check_grid_textures(s, self.limits)
        check_framebuffers(s, self.limits)
        check_cascade_limits(s.grid_size, s.cascades, s.grid_format,
                             s.geometry_volume != "off", 0, self.limits.max_texture_units,
                             sh_groups=3 if s.sh_order == 2 else 1)
        check_memory(s, self.memory_budget_bytes)

    def __enter__(self) -> "Pipeline":
        return self

    def __exit__(self, *exc_info) -> None:
        self.release()

    def release(self) -> None:
        if self.job is not None:
            self.job.cancel()
        for stage in (self.light_views, self._inject, self._geometry, self._gbuffer,
                      self._gather, self._fog, self._display, self._preview_gather):
            if stage is not None:
                stage.release()
        self._preview_gather, self.preview_textures = None, None
        self._release_levels(0)
        self.scene_state.release()
        self.programs.release()
        self.keys.clear()
        if self._owns_context:
            from explorer.gl.context import release_headless_context

            release_headless_context(self.ctx)

    # ------------------------------------------------------------------ what a Job calls
    def extra_input(self, stage: str, job: Job) -> object:
        """Inputs of ``stage`` besides Settings fields and upstream stages: hand-made VPLs
        (downsample), the display scale override (display)."""
        if stage == "downsample":
            return job.vpls_key
        return self.display_scale_override if stage == "display" else None

    def _audit_mode(self, job: Job, resolution: int) -> str:
        """The audit mode a ``resolution``³ level propagates with for ``job``: the one it
        asks for, but ``flux`` for ``full`` when the per-cell records do not fit this
        driver's storage blocks (:func:`audit_fits`; the flux needs no records)."""
        if job.need_audit == "full" and not audit_fits(resolution, self.limits):
            return "flux"
        return job.need_audit

    def satisfied(self, stage: str, job: Job) -> bool:
        """Whether the last completed run of ``stage`` has everything ``job`` asks for
        (the propagation's kept steps and audit)."""
        if stage != "propagate":
            return True
        for level in self._levels[: len(self._specs)]:
            output = level.output
            if output is None:
                return False
            if job.keep_steps and output.steps is None:
                return False
            if not audit_covers(output.audit.mode, self._audit_mode(job, level.injected
                                                                     .resolution)):
                return False
        return True

    def evaluate(self, stage: str, job: Job) -> object:
        """The value of a by-value stage (``grid``: the tuple of cascade specs)."""
        if stage != "grid":
            raise ValueError(f"{stage} is not a by-value stage")
        self._specs = frame_specs(job.settings, self.scene_state.for_settings(job.settings))
        return tuple(self._specs)

    def stage_units(self, stage: str, job: Job) -> int:
        """The total of ``stage``'s progress count: its units, or for the propagation its
        steps (all levels together; each step is one or more slabs)."""
        if stage in ("inject", "geometry"):
            return len(self._specs)
        if stage == "rsm":
            scene = self.scene_state.for_settings(job.settings)
            return len(LightViews.of(scene, job.settings.rsm_size)) + 1
        if stage == "gbuffer":
            return 1 + len(gbuffer_pass.TARGETS)
        if stage == "gather":
            return len(bands((job.settings.width, job.settings.height))) + \
                len(gather_pass.TARGETS) + 1
        if stage == "display":
            return 2
        if stage == "fog" and job.settings.fog:
            return len(bands((job.settings.width, job.settings.height))) + \
                len(fog_pass.TARGETS)
        if stage == "propagate":
            return max(1, sum(cascade_iterations(job.settings, k)
                              for k in range(len(self._specs))))
        return 1

    def stage_work(self, stage: str, job: Job) -> Iterator[int | None]:
        """The work of ``stage`` as a generator: each ``next()`` does one unit and yields
        the progress in the stage's own count (None: one more unit) until the last unit
        ends it."""
        method = getattr(self, f"_stage_{stage}")
        if inspect.isgeneratorfunction(method):
            return method(job)
        return single_unit(lambda: method(job))

    def finish_job(self, job: Job) -> FrameResult:
        """The FrameResult of a job whose stages are all complete."""
        self.last_result = frame_result(
            job.settings, self._arrays, list(zip(self._specs, self._levels)),
            self.scene_state.scene, self._warnings, self.timer, job.progress.stages_run,
            self._display_scale)
        return self.last_result

    def show_preview(self, job: Job, scale: float = 1.0) -> bool:
        """Gather and display the accumulation as it is now (see :meth:`Job.preview`);
        the gather and display stages then run again when the job gets there.
        ``scale`` < 1: gather it at that fraction of each edge into targets of its own
        instead, and no display pass (the window's quick previews: the job's gather and
        display stay as they are); :attr:`preview_textures` then holds that picture."""
        if any(level.accumulation_textures is None for level in self._levels[:len(self._specs)]):
            return False
        s = job.settings
        if scale < 1.0:
            if self._preview_gather is None:
                self._preview_gather = GatherPass(self.ctx, self.programs)
            self._gather_levels(s, into=self._preview_gather,
                                size=reduced_size(self._gbuffer.size, scale))
            targets = self._preview_gather.targets
            self.preview_textures = (targets["direct"], targets["indirect"],
                                     self._gbuffer.textures[2])
            return True
        self.keys.pop("gather", None)
        self.keys.pop("display", None)
        self.timer.timed("gather", lambda: self._gather_levels(s))
        # the last frame's display scale: the auto exposure needs the read-back images,
        # and a steady exposure shows the light growing; the fog is marched once the
        # propagation is done, so a preview shows the surfaces without it
        self._show(s, self._display_scale if self.display_scale_override is None
                   else self.display_scale_override, fog=False)
        self.preview_textures = self.linear_textures
        return True

    # ------------------------------------------------------------------ stages
    # One method per stage of explorer/lpv/stages.py: a plain method is one unit of work,
    # a generator yields after each unit but the last (see stage_work).
    def _stage_scene(self, job: Job) -> None:
        """Load the mesh (once per scene name) and pose its objects
        (:meth:`SceneState.load_and_pose`)."""
        base = self.scene_state.load_and_pose(job.settings)
        self._warnings["scene"] = guards.found(
            guards.scale_warning(base.bounds_min, base.bounds_max))

    def _stage_gbuffer(self, job: Job) -> Iterator[None]:
        """The G-buffer, then the read-back of each of its textures (one unit each)."""
        s = job.settings
        scene = self.scene_state.for_settings(s)
        self.timer.timed("gbuffer", lambda: self._gbuffer.run(
            self.scene_state.buffers, scene, (s.width, s.height)))
        yield
        arrays = yield from read_back(self._gbuffer.textures)
        self._arrays["gbuffer"] = tuple(arrays)
        self._warnings["gbuffer"] = guards.arrays_warnings("gbuffer", arrays, s)

    def _stage_rsm(self, job: Job) -> Iterator[None]:
        """One RSM per view of every light that shines (a unit each), then the atlas of
        their shadow maps and VPLs (several views) and the read-back (one unit)."""
        s = job.settings
        views = LightViews.of(self.scene_state.for_settings(s), s.rsm_size)
        check_memory(s, self.memory_budget_bytes, views=len(views))
        yield from self.light_views.render(views, self.scene_state.buffers,
                                           self.limits.max_framebuffer_size)
        arrays, checked = self.light_views.rsm_read_back()
        self._arrays.update(arrays)
        self._warnings["rsm"] = guards.arrays_warnings("rsm", checked, s)

    def _stage_downsample(self, job: Job) -> None:
        """The VPLs the injection reads (explorer/lpv/light_views.py ``choose_vpls``)
        and their read-back."""
        s = job.settings
        self._arrays.update(self.light_views.choose_vpls(s, job.vpls, self._specs[0],
                                                         self.limits.max_framebuffer_size))
        if job.vpls is None:   # hand-made VPLs are the caller's: a NaN shows up at inject
            self._warnings["downsample"] = guards.arrays_warnings(
                "downsample", [self._arrays["vpls"].flux], s)

    def _stage_inject(self, job: Job) -> Iterator[None]:
        s = job.settings
        levels = self._levels_for(self._specs)
        self.timer.reset("inject")
        for k, (level, spec) in enumerate(zip(levels, self._specs)):
            grid = level.grid(spec.resolution, s.grid_format, s.sh_order)
            self.timer.timed("inject", lambda: self._inject.run(
                self.light_views.vpl_textures, spec, s.corrections, s.injection_mode, grid,
                s.injection_offset_cells), accumulate=True)
            if s.debug_nan:
                check_finite(grid.read(), level_pass_name("inject", k, len(levels)))
            if k < len(levels) - 1:
                yield

    def _stage_geometry(self, job: Job) -> Iterator[None]:
        s = job.settings
        levels = self._levels_for(self._specs)
        if s.geometry_volume == "off":
            self.timer.forget("geometry")
            self._warnings["geometry"] = []
            for level in levels:
                level.release_volume()
            return
        occluders = self.light_views.occluders(hand_made=job.vpls is not None)
        camera = self._camera_surfels(s) if s.uses_camera_occluders else None
        self.timer.reset("geometry")
        warnings = []
        for k, (level, spec) in enumerate(zip(levels, self._specs)):
            volume = level.geometry_volume(spec.resolution, s.grid_format)
            self.timer.timed("geometry", lambda: self._geometry.run(
                occluders, spec, s.corrections, s.geometry_volume, volume, camera),
                accumulate=True)
            level.geometry = volume.read()
            warnings += guards.arrays_warnings(level_pass_name("geometry", k, len(levels)),
                                               [level.geometry], s)
            if k < len(levels) - 1:
                yield
        self._warnings["geometry"] = warnings

    def _camera_surfels(self, s: Settings) -> CameraSurfels:
        """The G-buffer as occluder surfels, tested against every RSM view's shadow map
        (docs/MODEL.md "Camera occluders")."""
        camera, lights = self.scene_state.scene.camera, self.light_views
        return CameraSurfels(
            position=self._gbuffer.position, normal=self._gbuffer.normal,
            albedo=self._gbuffer.albedo, view=camera.view_matrix(),
            pixel_area=camera_pixel_area(camera.fov_y_degrees, s.height),
            shadow=lights.rsm_textures, views=tuple(lights.views),
            tiles=tuple(lights.shadow_tiles))

    def _stage_propagate(self, job: Job) -> Iterator[int]:
        """Every level's propagation: a unit to start each level (grid_0 into the
        accumulation), one per slab of a step (explorer/lpv/propagate.py ``slabs``), the
        levels interleaved so that each is as far along as the others (a progressive
        picture shows all cascades growing together), and two to finish each level (its
        audit, then its read-back). Yields the steps done, all levels together."""
        s = job.settings
        levels = self._levels[: len(self._specs)]
        self.timer.reset("propagate")
        audit = [self._audit_mode(job, spec.resolution) for spec in self._specs]
        steps = [cascade_iterations(s, k) for k in range(len(levels))]
        more = countdown(3 * len(levels) + sum(
            count * len(slabs(spec.resolution)) for count, spec in zip(steps, self._specs)))
        try:
            for k, (level, spec) in enumerate(zip(levels, self._specs)):
                level.output = None
                level.running = self.timer.timed("propagate", lambda: level.propagate.start(
                    level.injected, spec, s.corrections, steps[k], level.volume,
                    keep_steps=job.keep_steps, bounces=s.bounces, audit=audit[k]),
                    accumulate=True)
                if more():
                    yield 0
            while not all(level.running.finished for level in levels):
                behind = min((lv for lv in levels if not lv.running.finished),
                             key=lambda lv: lv.running.fraction)
                self.timer.timed("propagate", behind.running.advance, accumulate=True)
                if more():
                    yield sum(level.running.done for level in levels)
            warnings = []
            for k, level in enumerate(levels):
                level.output = self.timer.timed("propagate", level.running.finish,
                                           accumulate=True)
                if more():
                    yield sum(steps)
                level.accumulated = yield from read_in_units(level.output.accumulated,
                                                             sum(steps))
                warnings += guards.found(guards.flux_warning(
                    level_pass_name("inject", k, len(levels)), level.output.audit.injected,
                    s.corrections))
                warnings += guards.arrays_warnings(
                    level_pass_name("propagate", k, len(levels)), [level.accumulated], s)
                if audit[k] != job.need_audit:
                    warnings.append(audit_skipped_warning(self._specs[k].resolution,
                                                          self.limits))
                if more():
                    yield sum(steps)
            self._warnings["propagate"] = warnings
        finally:
            for level in levels:
                level.running = None

    def _stage_gather(self, job: Job) -> Iterator[None]:
        """The gather in bands of rows (explorer/lpv/gather.py ``bands``), one per unit,
        then the read-back of each target (one unit each)."""
        s = job.settings
        self.timer.reset("gather")
        for band in bands((s.width, s.height)):
            self.timer.timed("gather", lambda: self._gather_levels(s, band), accumulate=True)
            yield
        targets = self._gather.targets
        names = gather_pass.TARGETS
        arrays = yield from read_back([targets[name] for name in names])
        yield       # the sums and the checks of the arrays: a unit of their own
        self._arrays["gather"] = dict(zip(names, arrays))
        received = self._arrays["gather"]["received"][..., :3]
        self._arrays["gathered"] = np.add.reduce(received.reshape(-1, 3), axis=0,
                                                 dtype=np.float64)
        self._warnings["gather"] = guards.arrays_warnings("gather", arrays, s)

    def _stage_fog(self, job: Job) -> Iterator[None]:
        """The fog's march in bands of rows (one per unit), then the read-back of its two
        targets (docs/MODEL.md "Fog"); nothing while ``fog`` is off."""
        s = job.settings
        if not s.fog:
            self.timer.forget("fog")
            self._arrays["fog"] = None
            self._warnings["fog"] = []
            return
        levels = self._levels[: len(self._specs)]
        cascades = [CascadeInput(spec, level.accumulation_textures)
                    for spec, level in zip(self._specs, levels)]
        medium, lights = Medium.of(s), self.light_views
        self.timer.reset("fog")
        for band in bands((s.width, s.height)):
            self.timer.timed("fog", lambda: self._fog.run(
                self._gbuffer, lights.rsm_textures, lights.views, self.scene_state.scene,
                cascades, medium, sh_order=levels[0].injected.sh_order,
                shader_filter=self._gather.shader_filter, rows=band,
                shadow_tiles=lights.shadow_tiles), accumulate=True)
            yield
        targets = self._fog.targets
        direct, lpv = yield from read_back([targets[name] for name in fog_pass.TARGETS])
        self._arrays["fog"] = FogImages(direct[..., 3].copy(), direct[..., :3], lpv[..., :3])
        self._warnings["fog"] = guards.arrays_warnings("fog", [direct, lpv], s)

    def _stage_display(self, job: Job) -> Iterator[None]:
        """Two units: the display scale (the auto exposure measures the read-back image on
        the CPU), then the display pass."""
        s = job.settings
        self._display_scale = self._frame_display_scale(s)
        yield
        self._show(s, self._display_scale)

    def _show(self, s: Settings, scale: float, fog: bool = True) -> None:
        """The display pass on the gather's targets as they are now (and the fog's, when
        the frame has one and ``fog``)."""
        targets = self._gather.targets
        fog_targets = None
        if fog and s.fog and self._arrays.get("fog") is not None:
            fog_targets = tuple(self._fog.targets[name] for name in fog_pass.TARGETS)
        self.timer.timed("display", lambda: self._display.run(
            targets["direct"], targets["indirect"], s.exposure, s.indirect_only, s.tone_map,
            scale, fog_targets))

    def _frame_display_scale(self, s: Settings) -> float:
        """The display scale of the frame just gathered: the override, or the auto
        exposure of its unexposed image over the pixels that show a surface (measured
        once per gathered frame and ``indirect_only``; an exposure change reuses it)."""
        if self.display_scale_override is not None:
            return float(self.display_scale_override)
        if not s.auto_exposure:
            return 1.0
        return self._auto_exposure.scale(self._arrays["gather"],
                                         self._arrays.get("fog") if s.fog else None,
                                         s.indirect_only, self._arrays["gbuffer"][0])

    # ------------------------------------------------------------------ helpers
    def _levels_for(self, specs: list[GridSpec]) -> list[CascadeLevel]:
        """One :class:`CascadeLevel` per spec (extra levels are released)."""
        self._release_levels(len(specs))
        while len(self._levels) < len(specs):
            self._levels.append(CascadeLevel(self.ctx, self.programs))
        return self._levels

    def _release_levels(self, keep: int) -> None:
        for level in self._levels[keep:]:
            level.release()
        del self._levels[keep:]

    def _gather_levels(self, s: Settings, rows: tuple[int, int] | None = None,
                       into: GatherPass | None = None,
                       size: tuple[int, int] | None = None) -> None:
        """The gather of every level's accumulation as it is now (docs/MODEL.md "Final
        gather", "Cascades"), of the rows ``rows`` or the whole image; ``into``/``size``:
        another gather pass's targets, at that size (a reduced preview)."""
        levels = self._levels[: len(self._specs)]
        textures = [level.accumulation_textures for level in levels]
        cascades = None
        if len(levels) > 1:
            cascades = [CascadeInput(spec, t) for spec, t in zip(self._specs, textures)]
        lights = self.light_views
        (into or self._gather).run(
            self._gbuffer, lights.rsm_textures, lights.views, textures[0], self._specs[0],
            s.gather_damping, cascades=cascades, sh_order=levels[0].injected.sh_order,
            rows=rows, shadow_kernel=s.shadow_kernel, shadow_tiles=lights.shadow_tiles,
            glossy=Glossy.of(s, self.scene_state.scene.camera.eye), size=size)

    def propagation_inputs(self, level: int = 0):
        """``(injected grid, GridSpec, geometry volume or None)`` of cascade ``level``'s
        last propagation, on the GPU (``lpv-explorer bench`` propagates them again with
        its baseline kernel)."""
        cascade = self._levels[level]
        return cascade.injected, self._specs[level], cascade.volume


def render(settings: Settings) -> FrameResult:
    """One frame with a throw-away headless pipeline (scripts, notebooks)."""
    with Pipeline(settings) as pipeline:
        return pipeline.run()
