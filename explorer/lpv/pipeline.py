"""The LPV frame: RSM -> downsample -> inject (+ geometry volume) -> propagate -> gather ->
fog -> display.

:class:`Pipeline` holds the services every stage uses (the GL context, its programs, the
timer, the driver's limits, the scene and the light views), one object per stage
(:attr:`Pipeline.stages`, explorer/lpv/stages/, made from the declared list
:data:`explorer.lpv.stage_list.STAGE_LIST`) and the :class:`FrameState` they hand on to
each other. A frame is one loop over the declared stages in their execution order
(:class:`~explorer.lpv.job.Job`): a stage runs only when its key changed (the Settings
fields it reads, declared once in the settings schema, the output keys of its upstream
stages and its extra inputs; explorer/lpv/cache_keys.py, table: ``stages.describe()``), its
units of work one after another. Every stage is timed, its output is checked for NaN and
infinity (warnings in ``FrameResult.warnings``, or a FloatingPointError with
``debug_nan``), and what ``FrameResult`` holds is read back when the stage runs.

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

import dataclasses
from collections.abc import Callable, Iterator

import moderngl
import numpy as np

from explorer.gl.program import ProgramCache
from explorer.lpv.cascades import check_limits as check_cascade_limits
from explorer.lpv.frame import FrameResult, LevelResult, frame_result
from explorer.lpv.frame_state import FrameState
from explorer.lpv.job import Job, ProgressCallback
from explorer.lpv.light_views import LightViews
from explorer.lpv.limits import (
    DEFAULT_MEMORY_BUDGET,
    DriverLimits,
    check_framebuffers,
    check_grid_textures,
    check_memory,
)
from explorer.lpv.passes.gather import GatherPass, reduced_size
from explorer.lpv.scene_state import SceneState
from explorer.lpv.settings import VIEWS, Settings
from explorer.lpv.stage_list import STAGES
from explorer.lpv.stages import Stage, make_stages
from explorer.lpv.stages.display import Params as DisplayParams
from explorer.lpv.timing import PassTimer
from explorer.lpv.views import render_view
from explorer.lpv.vpl import VplArrays
from explorer.scene import Scene

__all__ = ["FrameResult", "LevelResult", "Pipeline", "render"]


class Pipeline:
    """Runs the declared stages of an LPV frame (one object each, :attr:`stages`) with the
    services they share, and keeps what they left (:attr:`state`) between runs."""

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
        self.steps_levels: int | None = None
        """How many cascade levels, finest first, keep their propagation steps for a job
        with ``keep_steps`` (None: every level, as a dump writes them; the window shows
        only the finest's and sets 1: at 64³ a level's steps are about 200 MiB)."""
        """Refuse settings whose textures and read-back arrays would need more bytes."""
        self.timer = PassTimer(ctx)
        """Times every pass (``timings_ms``, ``timing_methods``; explorer/lpv/timing.py)."""
        self.light_views = LightViews(ctx, self.programs, self.timer)
        """The RSM and downsample passes of every light view, their atlases and what the
        ``rsm`` and ``downsample`` stages left (explorer/lpv/light_views.py)."""
        self.scene_state = SceneState(ctx)
        """The loaded and posed scene, its vertex buffer and the frame's scene with the
        Settings applied (explorer/lpv/scene_state.py)."""
        self.display_scale_override: float | None = None
        """Show frames with this display scale instead of their own (the window shows
        configuration B at A's exposure); None = the frame's own (auto exposure or 1). An
        input of the display stage: changing it runs that stage alone."""
        self.state = FrameState()
        """What each stage left for the next (explorer/lpv/frame_state.py)."""
        self.stages: dict[str, Stage] = make_stages(self)
        """Stage name -> its object (explorer/lpv/stages/), in the declared order
        (:data:`explorer.lpv.stage_list.STAGE_LIST`)."""
        self._preview_gather: GatherPass | None = None
        """The reduced previews' own targets (made at the first one)."""
        self.preview_textures: tuple | None = None
        """``(direct, indirect, albedo)`` of the last preview (:meth:`show_preview`)."""
        self.keys: dict[str, object] = {}
        """Stage -> key of its last completed run (forgotten while it runs)."""
        self.out_keys: dict[str, object] = {}
        """By-value stage -> its last value (the grid specs)."""
        self.unit_ms: dict[str, float] = {}
        """Stage -> measured milliseconds of its last unit of work (a job's budget)."""
        self.unit_ms_at: dict[tuple[str, int], float] = {}
        """(stage, unit number within the stage) -> milliseconds it last took: a stage's
        units differ (a propagation's slabs, then its audit and read-backs), so a job
        sizes its next unit by the same unit of the last run (``Job.next_unit_ms``)."""
        self.unit_ms_sized: dict[tuple[str, int, int], float] = {}
        """(stage, unit number, size) -> milliseconds it last took at that size, for the
        stages whose work grows with the pixels or the grid's cells (``Job.size_of``: a
        drag's reduced frames and the full-size one after it keep their own, a 32³ grid's
        units and a 64³ one's)."""
        self.unit_pixels: dict[str, int] = {}
        """Such a stage -> the size (pixels or cells) of its last unit measured."""
        self.key_memo: dict[str, tuple] = {}
        """Stage -> what its last key was made of, and the key
        (:func:`explorer.lpv.cache_keys.remembered_stage_key`)."""
        self._limits_checked: tuple[Settings, int] | None = None
        """The Settings object and memory budget :meth:`start` last checked."""
        self.job: Job | None = None
        """The job in progress, if any."""
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
        texture = self.stages["display"].display.texture
        if texture is None:
            raise RuntimeError("the pipeline has not run yet: call run() first")
        return texture

    @property
    def linear_textures(self) -> tuple[moderngl.Texture, moderngl.Texture, moderngl.Texture]:
        """``(direct, indirect, albedo)``: the gather's linear ``rgba32f`` radiance and the
        G-buffer's albedo (w = 1 on a surface), as the last gather or preview left them
        (the window copies them and applies the display itself, explorer/ui/picture.py).
        They are rewritten while a job runs."""
        targets, gbuffer = self.state.gather_pass.targets, self.state.gbuffer_pass
        if not targets or not gbuffer.textures:
            raise RuntimeError("the pipeline has not gathered yet: call run() first")
        return targets["direct"], targets["indirect"], gbuffer.albedo

    @property
    def surface_textures(self) -> tuple[moderngl.Texture, moderngl.Texture] | None:
        """``(position, normal)``: the G-buffer's, which mark the geometry's edges in the
        albedo view (explorer/lpv/surface_edges.py); None before the first G-buffer."""
        gbuffer = self.state.gbuffer_pass
        if gbuffer is None or not gbuffer.textures:
            return None
        return gbuffer.position, gbuffer.normal

    @property
    def fog_textures(self) -> tuple[moderngl.Texture, moderngl.Texture] | None:
        """``(fog_direct, fog_lpv)``: the fog pass's ``rgba32f`` targets of the last frame
        (the direct light's in-scattered radiance with the transmittance in w, the LPV's
        in-scattered radiance), which the display composes over :attr:`linear_textures`
        (docs/MODEL.md "Fog"); None when that frame has no fog."""
        if not self.settings.fog or self.state.fog is None:
            return None
        targets = self.state.fog_pass.targets
        return targets["fog_direct"], targets["fog_lpv"]

    def start(self, settings: Settings | None = None, keep_steps: bool = False,
              vpls: VplArrays | None = None, need_audit: str | bool = True,
              progress: ProgressCallback | None = None) -> Job:
        """A :class:`~explorer.lpv.job.Job` for a frame with ``settings`` (default: the
        last ones), cancelling the job in progress; a request past the limits raises a
        one-line ValueError before anything is allocated, and asking again for the frame in
        progress returns that job (a caller may start every frame).

        ``keep_steps`` keeps grid_0..grid_N of every cascade (the first
        :attr:`steps_levels`); ``need_audit`` is what the
        energy audit measures (:data:`explorer.lpv.audit.AUDIT_MODES`; True ``full``, False
        ``off``; a later job that needs more propagates again); ``vpls`` are injected
        instead of the RSM's (which still renders the direct light and its shadow)."""
        settings = self.settings if settings is None else settings
        current = self.job
        if current is not None and current.asks_for(settings, keep_steps, need_audit, vpls):
            current.progress_callback = progress
            return current           # the same frame: carry on where it is
        if current is not None:
            current.cancel()
        self.settings = settings
        checked = self._limits_checked
        if checked is None or checked[0] is not settings or \
                checked[1] != self.memory_budget_bytes:
            self.check_limits(settings)        # Settings are frozen: once per object
            self._limits_checked = (settings, self.memory_budget_bytes)
        self.job = Job(self, self.settings, keep_steps, need_audit, vpls, progress)
        return self.job

    def run(self, settings: Settings | None = None, keep_steps: bool = False,
            vpls: VplArrays | None = None, need_audit: str | bool = True,
            progress: ProgressCallback | None = None) -> FrameResult:
        """Render a frame at once; only the stages whose inputs changed run again.
        ``progress(stage, done, total)`` is called as it goes (see :meth:`start` for the
        other options). An exception, KeyboardInterrupt included, leaves the unfinished
        stage to run again next time and propagates. Its passes are timed one by one
        (a caller of ``run`` waits for the frame anyway: its timings are this frame's)."""
        job = self.start(settings, keep_steps, vpls, need_audit, progress)
        queued, self.timer.queued = self.timer.queued, False
        try:
            job.advance(None)
        finally:
            self.timer.queued = queued
        return job.result

    def invalidate(self, stage: str | None = None) -> None:
        """Make the next run redo ``stage`` and every stage after it in
        :data:`~explorer.lpv.stage_list.STAGES` (all stages when None), e.g. to time a whole
        frame or after editing a scene file."""
        if stage is not None and stage not in STAGES:
            raise ValueError(f"unknown stage {stage!r}; stages are {STAGES}")
        first = STAGES.index(stage) if stage is not None else 0
        if first == 0:
            self.scene_state.forget()
        for name in STAGES[first:]:
            self.keys.pop(name, None)

    def reload_scene(self, scene: Scene) -> None:
        """Show ``scene`` from the next run in place of the scene these Settings name, as
        loaded before (its file was edited; the caller read and checked it, so a broken
        edit never reaches the pipeline). The job in progress is cancelled and every stage
        runs again."""
        if self.job is not None:
            self.job.cancel()
            self.job = None
        self.invalidate()
        self.scene_state.adopt(self.settings.scene, scene)

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
        return self.state.gather.gathered

    def check_limits(self, s: Settings) -> None:
        """A one-line ValueError when ``s`` asks for more than the driver or the memory
        budget allows (explorer/lpv/limits.py)."""
        check_grid_textures(s, self.limits)
        check_framebuffers(s, self.limits)
        check_cascade_limits(s.grid_shape, s.cascades, s.grid_format,
                             s.geometry_volume != "off", 0, self.limits.max_texture_units,
                             sh_groups=3 if s.sh_order == 2 else 1)
        check_memory(s, self.memory_budget_bytes)

    def __enter__(self) -> Pipeline:
        return self

    def __exit__(self, *exc_info) -> None:
        self.release()

    def release_between_runs(self) -> int:
        """Release the GPU memory only a job in progress uses (the levels' ping and pong
        grids, :meth:`CascadeLevel.release_between_runs`, and the stages' read-backs
        already taken, :meth:`Stage.release_between_runs`), when no job is in progress
        (the window calls it once it falls idle); the next job makes them anew. Returns
        the bytes released."""
        if self.job is not None and not self.job.done:
            return 0
        return (sum(level.release_between_runs() for level in self.state.levels)
                + sum(stage.release_between_runs() for stage in self.stages.values()))

    def release(self) -> None:
        if self.job is not None:
            self.job.cancel()
        for owner in (self.light_views, *self.stages.values(), self._preview_gather):
            if owner is not None:
                owner.release()
        self._preview_gather, self.preview_textures = None, None
        self.state.release_levels(0)
        self.scene_state.release()
        self.programs.release()
        self.keys.clear()
        self.key_memo.clear()
        if self._owns_context:
            from explorer.gl.context import release_headless_context

            release_headless_context(self.ctx)

    # ------------------------------------------------------------------ what a Job calls
    # The Job runs the declared stages in order (explorer/lpv/job.py); each of these hands
    # the call to the stage's object (explorer/lpv/stages/).
    def extra_input(self, stage: str, job: Job) -> object:
        """Inputs of ``stage`` besides Settings fields and upstream stages: hand-made VPLs
        (downsample), the display scale override (display)."""
        return self.stages[stage].extra_input(job)

    def satisfied(self, stage: str, job: Job) -> bool:
        """Whether the last completed run of ``stage`` has everything ``job`` asks for
        (the propagation's kept steps and audit)."""
        return self.stages[stage].satisfied(job)

    def evaluate(self, stage: str, job: Job) -> object:
        """The value of a by-value stage (``grid``: the tuple of cascade specs)."""
        return self.stages[stage].evaluate(job)

    def stage_units(self, stage: str, job: Job) -> int:
        """The total of ``stage``'s progress count: its units, or for the propagation its
        steps (all levels together; each step is one or more slabs)."""
        return self.stages[stage].units(job)

    def stage_work(self, stage: str, job: Job) -> Iterator[int | None]:
        """The work of ``stage`` as a generator: each ``next()`` does one unit and yields
        the progress in the stage's own count (None: one more unit) until the last unit
        ends it."""
        return self.stages[stage].work(job)

    def finish_job(self, job: Job) -> FrameResult:
        """The FrameResult of a job whose stages are all complete (with the steps only
        when the job asked for them: the pipeline keeps none past such a job)."""
        if not job.keep_steps:
            self.state.drop_steps()
        self.last_result = frame_result(job.settings, self.state, self.scene_state.scene,
                                        self.timer, job.progress.stages_run)
        return self.last_result

    def show_preview(self, job: Job, scale: float = 1.0, injected: bool = False) -> bool:
        """Gather and display the accumulation as it is now (see :meth:`Job.preview`);
        the gather and display stages then run again when the job gets there.
        ``scale`` < 1: gather it at that fraction of each edge into targets of its own
        instead, and no display pass (the window's quick previews: the job's gather and
        display stay as they are); :attr:`preview_textures` then holds that picture.
        ``injected``: gather the injected grids instead (grid_0, what the accumulation
        holds before the first step: the job's injection is done, its propagation has
        no step yet)."""
        if injected:
            if any(level.injected is None for level in self.state.cascades):
                return False
            grid = self.state.injected_grid()
        elif any(level.accumulation_textures is None for level in self.state.cascades):
            return False
        else:
            grid = None
        s, gather = job.settings, self.stages["gather"]
        if scale < 1.0:
            if self._preview_gather is None:
                self._preview_gather = GatherPass(self.ctx, self.programs)
            gather.gather_levels(s, into=self._preview_gather,
                                 size=reduced_size(self.state.gbuffer_pass.size, scale),
                                 grid=grid)
            targets = self._preview_gather.targets
            self.preview_textures = (targets["direct"], targets["indirect"],
                                     self.state.gbuffer_pass.albedo)
            return True
        self.keys.pop("gather", None)
        self.keys.pop("display", None)
        self.timer.timed("gather", lambda: gather.gather_levels(s, grid=grid))
        # the last frame's display scale: the auto exposure needs the read-back images,
        # and a steady exposure shows the light growing; the fog is marched once the
        # propagation is done, so a preview shows the surfaces without it
        scale = self.state.display_scale if self.display_scale_override is None \
            else self.display_scale_override
        self.stages["display"].show(DisplayParams.of(s), scale, fog=False)
        self.preview_textures = self.linear_textures
        return True

    def propagation_inputs(self, level: int = 0):
        """``(injected grid, GridSpec, geometry volume or None)`` of cascade ``level``'s
        last propagation, on the GPU (``lpv-explorer bench`` propagates them again with
        its baseline kernel)."""
        cascade = self.state.levels[level]
        return cascade.injected, self.state.specs[level], cascade.volume


def render(settings: Settings | None = None, *, vpls: VplArrays | None = None,
           keep_steps: bool = False, need_audit: str | bool = True,
           ctx: moderngl.Context | None = None, **changes) -> FrameResult:
    """One frame with a throw-away pipeline (scripts, notebooks), headless unless ``ctx``
    is given: ``settings`` (default ``Settings()``) with ``changes`` applied by
    :meth:`Settings.with_changes` (so ``corrections="original"`` names a preset and a
    dict changes single switches); ``vpls``, ``keep_steps`` and ``need_audit`` as for
    :meth:`Pipeline.start`. A bad value raises a one-line ValueError naming the field.

    >>> from explorer.lpv import render
    >>> frame = render(grid_size=16, iterations=8, width=160, height=120)  # doctest: +SKIP
    >>> frame.audit.gathered, frame.final_image.shape                       # doctest: +SKIP
    """
    settings = Settings() if settings is None else settings
    unknown = sorted(set(changes) - {f.name for f in dataclasses.fields(Settings)})
    if unknown:
        raise ValueError(f"unknown setting(s) {', '.join(unknown)}; see Settings' fields "
                         f"(lpv-explorer render --help lists them with their flags)")
    if changes:
        settings = settings.with_changes(**changes)
    with Pipeline(settings, ctx=ctx) as pipeline:
        return pipeline.run(keep_steps=keep_steps, vpls=vpls, need_audit=need_audit)
