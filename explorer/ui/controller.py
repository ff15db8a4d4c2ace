"""The window's pipeline controller: configurations A and B, their jobs within a frame
budget, progressive pictures, failures, hot reload and the display of each side, with no
window (tests drive it with a headless context).

Each frame the window shell calls :meth:`PipelineController.update` with the app state
and a budget in milliseconds. The controller

* asks each side's pipeline for the frame the state describes (:meth:`Pipeline.start`;
  a request that differs from the job in flight cancels it, and the pipeline keeps the
  stages that completed), and advances the jobs until the budget is spent, whole units of
  work at a time (explorer/lpv/job.py), both sides alternately in split view;
* publishes pictures: when a job finishes (at the full size), and
  (``AppState.progressive``) while the propagation runs, a preview of the accumulation so
  far after each few steps, gathered at :data:`PREVIEW_SCALE` of each edge (a quarter of
  the pixels: quick to gather and to copy), copied into the side's
  :class:`~explorer.ui.picture.Picture`; after a job's first preview, none while the
  finished frame is due within :data:`FINISH_SOON_S`;
* gives the pipelines more of each frame while the user leaves the window alone
  (:data:`QUIET_BUDGET_MS` once no input came for :data:`QUIET_AFTER_S`; the shell's
  ``input_pending`` is asked between units, and input drops the frame back to the
  budget at once; the background tasks keep to the frame budget);
* runs no stage for a display-only change: the pipeline's Settings have the display
  stage's fields pinned (:data:`PINNED_DISPLAY`), and exposure, tone curve, indirect
  only and the auto exposure of each side are the view composer's
  (:meth:`side_display`, explorer/ui/view_composer.py);
* renders at a reduced size while the camera is dragged (``interacting``): the largest
  of :data:`DRAG_SCALES` whose camera-dependent work (G-buffer, gather, display) fits the
  frame budget as last measured, and at the full size once the drag ends;
* keeps the last good result when a request fails (one message per failure; a scene
  that does not open restores the previous one), reloads changed shaders (a compile error
  keeps the last good program and shows the log), and advances the panels' background
  tasks (``runtime.services.tasks``, the Error panel's reference) in what is left of the budget.
"""

from __future__ import annotations

import sys
import time
import traceback
from collections import Counter
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Callable, Protocol

import numpy as np

from explorer.lpv.audit import audit_covers, audit_mode
from explorer.schema import stages_reading
from explorer.lpv.settings import Settings
from explorer.lpv.stage_list import PIXEL_STAGES
from explorer.lpv.stages import downstream
from explorer.ui.picture import Picture, SideDisplay, Stamp
from explorer.ui.scene_watch import SceneWatch
from explorer.ui.side_display import SIDES, picture_scale, side_display, update_side_exposures

if TYPE_CHECKING:
    import moderngl

    from explorer.gl.program import ProgramCache
    from explorer.lpv.frame import FrameResult
    from explorer.lpv.job import Job, Progress
    from explorer.scene import Scene
    from explorer.ui.state import AppState

PINNED_DISPLAY: dict[str, object] = {
    name: getattr(Settings(), name) for name in stages_reading(Settings, "display")}
"""The display stage's fields, fixed in what the pipelines run: the view composer applies
the real ones, so changing them runs no stage (exposure, tone map, indirect only, auto
exposure)."""
CAMERA_STAGES = frozenset(("grid", *PIXEL_STAGES))
"""What a camera move runs (with one cascade the grid stage only recomputes its specs; the
fog's march, when it is on, follows the view rays): the work per pixel that a drag's
reduced size makes cheaper, measured to choose that size. (With camera occluders a move
also re-runs the geometry volume and the propagation: such frames are not measured.)"""
DRAG_SCALES = (1.0, 0.5, 0.25)
"""Render-size factors tried while the camera is dragged, largest first."""
FIRST_DRAG_SCALE = 0.5
"""Used until a camera-only frame has been timed."""
FIRST_PICTURE_SCALE = 0.25
"""The first picture after launch renders at this fraction of the size (quick to show),
then the full size follows."""
MIN_RENDER_EDGE = 16
SHADER_POLL_S = 0.5
PREVIEW_INTERVAL_S = 0.25
"""Progressive pictures after the first of a job come at most this often ..."""
PREVIEW_SHARE = 0.1
"""... and take at most this share of the time: a preview gathers the image and the
window draws it, so the interval grows with what the last preview and a drawn frame
cost (at 64³ on llvmpipe about every 0.6 s; a quarter of the time, as before issue #10's
second round, made the converged picture come later than a window without previews)."""
PREVIEW_SCALE = 0.5
"""Progressive previews gather at this fraction of each edge (a quarter of the pixels;
the finished frame comes at the full size): a full-size preview cost as much as four
propagation steps at 32³ on llvmpipe (issue #10)."""
FINISH_SOON_S = 0.5
"""After a job's first preview no other comes once the finished frame is due within this
(the propagation's pace so far, then the gather and display as last timed): it would be
on screen too briefly to be worth its gather and its drawing. A short job (32³ on
llvmpipe) thus shows one growing picture, a long one (64³) several."""
QUIET_AFTER_S = 0.15
"""No input for this long: the user is watching, the pipelines get :data:`QUIET_BUDGET_MS`
a frame ..."""
QUIET_BUDGET_MS = 100.0
"""... (or the frame budget if larger) instead of the frame budget, so that fewer frames
share the work; the shell's ``input_pending`` is asked between units and input brings
the budget back at once. A frame stays within this plus one unit and a drawing."""
FINISHING_STAGES = frozenset(downstream("propagate")[1:])
"""The stages after the propagation (gather, fog, display): a job in one of them is
about to publish its finished frame, which is drawn, so its frame gets no quiet budget."""
MIN_TASK_MS = 2.0
"""Background tasks run when at least this much of the budget is left."""


class PipelineLike(Protocol):
    """What the controller calls and reads on a pipeline (explorer.lpv.pipeline.Pipeline):
    all of it, so that no call needs a fallback."""

    programs: "ProgramCache"
    settings: Settings
    """The settings of the last job started."""
    unit_ms: dict[str, float]
    """Stage -> milliseconds of its last unit of work (what fits a budget)."""
    unit_ms_at: dict[tuple[str, int], float]
    """(stage, unit number) -> milliseconds it last took (``Job.next_unit_ms``)."""
    preview_textures: tuple | None
    """The last reduced preview's linear textures (``Job.preview`` with a scale < 1)."""

    def start(self, settings: Settings, keep_steps: bool = ..., need_audit: str | bool = ...,
              progress: Callable[[str, int, int], None] | None = ...) -> "Job": ...
    def reload_shaders(self) -> bool: ...
    def reload_scene(self, scene: "Scene") -> None: ...
    def release(self) -> None: ...
    def view(self, name: str, **options) -> np.ndarray: ...
    @property
    def timings_ms(self) -> dict[str, float]: ...
    @property
    def linear_textures(self) -> tuple: ...
    @property
    def fog_textures(self) -> tuple | None: ...
    @property
    def base_scene(self) -> "Scene | None": ...


@dataclass(frozen=True)
class Request:
    """The frame one side's pipeline is asked for."""

    settings: Settings
    """What the pipeline runs: the side's settings with :data:`PINNED_DISPLAY` and, while
    interacting, a reduced size."""
    keep_steps: bool = False
    need_audit: str = "off"
    """The audit mode (explorer.lpv.audit.AUDIT_MODES) what is shown needs."""
    interactive: bool = False
    """Made while the camera is dragged (reduced size)."""

    def covered_by(self, done: "Request | None") -> bool:
        """Whether the frame ``done`` computed already has all this request asks for
        (the same settings, and its steps and audit when asked)."""
        return (done is not None and done.settings == self.settings
                and done.keep_steps >= self.keep_steps
                and audit_covers(done.need_audit, self.need_audit))


@dataclass(frozen=True)
class WorkUnit:
    """What one call into a side's job did this frame (the benchmark's frame profile)."""

    side: str
    what: str
    """The job's label after the call ("propagating 5/8", "done"), or "preview",
    "snapshot", a task's class name."""
    ms: float


@dataclass
class ControllerStatus:
    """What :meth:`PipelineController.update` did and where the work stands."""

    busy: bool = False
    """A job or a background task still has work: the window must keep drawing."""
    published: bool = False
    """A side has a new picture this frame."""
    labels: dict[str, str] = field(default_factory=dict)
    """Side -> its job's progress ("propagating 5/8"); absent when the side is idle."""
    work: list[WorkUnit] = field(default_factory=list)
    work_ms: float = 0.0
    failures: int = 0
    """Requests that failed this frame (a message was posted; the state may have been
    put back, e.g. a scene that does not open)."""

    @property
    def active(self) -> bool:
        """Anything happened or is still to happen: the window draws this frame."""
        return self.busy or self.published or bool(self.work) or self.failures > 0


@dataclass
class SideState:
    """One side's pipeline, job and last results."""

    name: str
    pipeline: PipelineLike | None = None
    picture: Picture | None = None
    job: "Job | None" = None
    request: Request | None = None
    """The request of the job in flight."""
    done: Request | None = None
    """The request of the last finished frame (what :attr:`result` shows)."""
    failed: Request | None = None
    result: "FrameResult | None" = None
    progress: "Progress | None" = None
    previewed: int = 0
    """Propagation steps of the job's last preview."""
    previewed_at: float = 0.0
    propagate_from: tuple[float, int] | None = None
    """(:attr:`job_ms`, steps) at the job's first preview: the propagation's pace since."""
    preview_ms: float = 0.0
    """What the side's last preview cost (gather, copy; display at the full size)."""
    previews_ms: float = 0.0
    """What the job's previews cost so far (in :attr:`job_ms`)."""
    job_ms: float = 0.0
    """Time spent in the job in flight so far."""
    serial: int = 0
    auto_scale: float | None = None
    """The auto exposure of the side's last picture (previews keep it: a steady
    exposure shows the light growing)."""
    scale_cache: dict = field(default_factory=dict)
    """(id(result), indirect_only) -> auto exposure scale."""
    warned: tuple[str, ...] = ()
    stage_runs: Counter = field(default_factory=Counter)
    """Stage -> how many times it started on this side (tests and the benchmark)."""


class PipelineController:
    """Owns the pipelines of sides A and B (module docstring)."""

    def __init__(self, ctx: "moderngl.Context", pipeline_class: Callable | None) -> None:
        from explorer.gl.program import ProgramCache

        self.ctx = ctx
        self.pipeline_class = pipeline_class
        self.programs = ProgramCache(ctx)
        """The pictures' copy program (the pipelines have their own caches)."""
        self.sides: dict[str, SideState] = {name: SideState(name) for name in SIDES}
        self.drag_scale = FIRST_DRAG_SCALE
        self.preview_interval_s = PREVIEW_INTERVAL_S
        """The shortest time between two previews of a job (0: after every step, and
        to the end)."""
        self.preview_scale = PREVIEW_SCALE
        """Fraction of each edge a progressive preview gathers (1: the full size)."""
        self.quiet_budget_ms = QUIET_BUDGET_MS
        """A frame's budget once no input came for :data:`QUIET_AFTER_S` (at least the
        frame budget; 0: never more than the frame budget)."""
        self.budget_used_ms = 0.0
        """The budget the last update worked to (the frame budget or the quiet one)."""
        self.draw_ms = 0.0
        """What the window spends drawing a frame (the shell's measure)."""
        self.camera_ms_per_pixel: float | None = None
        """Measured cost of the last camera-only frame per pixel."""
        self.camera_ms: dict[float, float] = {}
        """Drag scale -> milliseconds of the last camera-only frame at about that scale
        (chooses :attr:`drag_scale`)."""
        self.ran_settings: Settings | None = None
        """state.settings when A last finished a frame."""
        self.failed_settings: Settings | None = None
        """state.settings when A last failed (None once it finishes a frame again)."""
        self._good_scene: tuple | None = None
        self._defaults_for: str | None = None
        self.scene_watch = SceneWatch()
        """The files of the scene on screen (reloaded when edited)."""
        self._shader_poll = 0.0
        self._turn = 0
        self._first_done = False
        self._status = ControllerStatus()
        self._side_budget_ms = 30.0
        self._budget = _Budget(0.0, 0.0, 0.0, None)
        self.full_pixels = 0
        """Pixels of the full render size (the state's, each update)."""

    # ------------------------------------------------------------------ requests
    def settings_for(self, state: "AppState", side: str) -> Settings:
        """The Settings ``side`` shows: A's, and for B A's with the compare corrections
        and overrides (display fields as the user set them)."""
        a = state.settings
        if side == "A":
            return a
        return a.with_changes(corrections=state.compare_settings.corrections,
                              **dict(state.compare_overrides))

    def request_for(self, state: "AppState", side: str, need_audit: str | bool,
                    interacting: bool) -> Request:
        settings = self.settings_for(state, side).with_changes(**PINNED_DISPLAY)
        scale = 1.0
        if interacting:
            scale = self.drag_scale
        elif not self._first_done:
            scale = FIRST_PICTURE_SCALE
        # no edge below MIN_RENDER_EDGE, the aspect kept
        scale = min(max(scale, MIN_RENDER_EDGE / max(min(settings.width, settings.height), 1)),
                    1.0)
        if scale < 1.0:
            settings = settings.with_changes(width=int(round(settings.width * scale)),
                                             height=int(round(settings.height * scale)))
        return Request(settings, keeps_steps(state, side), audit_mode(need_audit),
                       interactive=scale < 1.0)

    def active_sides(self, state: "AppState") -> tuple[str, ...]:
        return SIDES if state.comparing else ("A",)

    # ------------------------------------------------------------------ the frame
    def update(self, state: "AppState", budget_ms: float, *,
               need_audit: str | bool = "off", interacting: bool = False,
               drag_budget_ms: float | None = None,
               draw_ms: float | None = None, quiet_s: float = 0.0,
               input_pending: Callable[[], bool] | None = None) -> ControllerStatus:
        """Start, advance and publish within ``budget_ms`` milliseconds (module
        docstring); fills ``state.runtime``. ``need_audit``: the audit mode what is
        drawn needs (explorer.lpv.audit.AUDIT_MODES; the window's
        ``runtime.audit_wanted``). ``drag_budget_ms``: what a frame may spend
        on the pipelines while the camera is dragged (the window's frame time for the
        drag's frame rate, less its own drawing; default ``budget_ms``): the drag scale
        is chosen so that a camera frame fits it, and a drag's frame gets that much.
        ``draw_ms``: what the window spends drawing a frame (paces the previews).
        ``quiet_s``: seconds since the last input; from :data:`QUIET_AFTER_S` on, the
        frame gets :attr:`quiet_budget_ms` unless ``input_pending()`` (asked between
        units) says input arrived, which ends it at ``budget_ms``."""
        status = self._status = ControllerStatus()
        if self.pipeline_class is None:
            return status
        if draw_ms is not None:
            self.draw_ms = draw_ms
        self._hot_reload(state)
        start = time.perf_counter()
        active = self.active_sides(state)
        drag_budget_ms = budget_ms if drag_budget_ms is None else drag_budget_ms
        if interacting:
            budget_ms = max(budget_ms, drag_budget_ms)
        base_ms = budget_ms
        if not interacting and quiet_s >= QUIET_AFTER_S:
            budget_ms = max(budget_ms, self.quiet_budget_ms)
        self._budget = _Budget(start, budget_ms, base_ms, input_pending)
        self._side_budget_ms = drag_budget_ms / len(active)
        self.full_pixels = state.settings.width * state.settings.height
        for name in active:
            self._ask(state, self.sides[name],
                      self.request_for(state, name, need_audit, interacting))
        running = [self.sides[name] for name in active if self.sides[name].job is not None]
        self._advance(state, running, status)
        # the panels' tasks keep to the frame budget: nobody asks for input inside them
        self._tasks(state, min(self._budget.left(), self._budget.base_left()), status)
        self.budget_used_ms = self._budget.ms
        for name in active:
            side = self.sides[name]
            if side.job is not None:
                status.busy = True
                status.labels[name] = (side.progress.label if side.progress is not None
                                       else "starting")
        if any(task.running for task in state.runtime.services.tasks):
            status.busy = True
        self._publish_runtime(state)
        status.work_ms = (time.perf_counter() - start) * 1e3
        return status

    def _ask(self, state: "AppState", side: SideState, request: Request) -> None:
        """Start a job for ``request`` unless the last frame or the job in flight already
        computes it, or it failed before."""
        if side.job is not None and side.request == request:
            return
        if side.job is None and (request.covered_by(side.done) or request == side.failed):
            return
        if side.job is not None and side.request.interactive and request.interactive:
            return     # a drag's frame finishes before the next starts: never starved
        try:
            if side.pipeline is None:
                side.pipeline = self.pipeline_class(request.settings, ctx=self.ctx)
            side.job = side.pipeline.start(
                request.settings, keep_steps=request.keep_steps, need_audit=request.need_audit,
                progress=_StageCounter(side.stage_runs))
        except Exception as exc:  # noqa: BLE001 - shown in the window, the app goes on
            self._failed(state, side, request, exc)
            return
        finally:
            _use_screen(self.ctx)
        side.request, side.previewed, side.job_ms = request, 0, 0.0
        side.previews_ms, side.propagate_from = 0.0, None
        side.progress = side.job.progress

    def _advance(self, state: "AppState", running: list[SideState],
                 status: ControllerStatus) -> None:
        """Advance the jobs until the budget is spent: the sides take turns (who goes
        first alternates between frames), each given an equal share of what is left; a
        side whose job has more work goes round again while its next unit still fits. At
        most one progressive preview per side and frame, before its first turn. With a
        quiet budget a turn is at most the frame budget long, so that input is looked for
        between turns, and a frame that publishes a preview (it is drawn) keeps to the
        frame budget."""
        if not running:
            return
        budget = self._budget
        self._turn = (self._turn + 1) % len(running)
        order = running[self._turn:] + running[:self._turn]
        previewed: set[str] = set()
        while order:
            left = budget.left()
            side = order.pop(0)
            if side.job is None:
                continue
            if budget.ms > budget.base_ms and side.job.stage in FINISHING_STAGES:
                # the job's finished frame is near, and it is drawn: the frame budget
                budget.ms = budget.base_ms
                left = budget.left()
            if side.name in previewed and not self._fits(side, left / (len(order) + 1)):
                continue
            if side.name not in previewed:
                previewed.add(side.name)
                self._preview_if_due(state, side, status)
                if status.published:    # this frame is drawn: no quiet budget on top
                    budget.ms = min(budget.ms, budget.base_ms)
                if side.job is None:
                    continue
                left = budget.left()
            share = max(left, 0.0) / (len(order) + 1)
            if budget.ms > budget.base_ms:
                share = min(share, budget.base_ms)
            self._step(state, side, share, status)
            if side.job is not None:
                order.append(side)

    @staticmethod
    def _fits(side: SideState, left_ms: float) -> bool:
        """Whether the next unit of ``side``'s job, as last measured, fits ``left_ms``."""
        return left_ms > 0.0 and side.job.next_unit_ms() <= left_ms

    def _step(self, state: "AppState", side: SideState, budget_ms: float,
              status: ControllerStatus) -> None:
        began = time.perf_counter()
        try:
            side.progress = side.job.advance(budget_ms)
        except Exception as exc:  # noqa: BLE001 - shown in the window, the app goes on
            request = side.request
            side.job, side.request = None, None
            self._failed(state, side, request, exc)
            return
        finally:
            _use_screen(self.ctx)
        elapsed = (time.perf_counter() - began) * 1e3
        side.job_ms += elapsed
        status.work.append(WorkUnit(side.name, side.progress.label, elapsed))
        if side.job.done:
            self._finished(state, side, status)

    def _preview_if_due(self, state: "AppState", side: SideState,
                        status: ControllerStatus) -> None:
        """A progressive picture when the propagation advanced since the last one."""
        progress = side.progress
        if (not state.progressive or progress is None or progress.stage != "propagate"
                or progress.done <= side.previewed):
            return
        began = time.perf_counter()
        if side.previewed > 0 and self.preview_interval_s > 0.0:
            cost_s = (side.preview_ms + self.draw_ms) / 1e3 / PREVIEW_SHARE
            if time.monotonic() - side.previewed_at < max(self.preview_interval_s, cost_s):
                return
            if self._finish_due_ms(side) < FINISH_SOON_S * 1e3:
                return      # the finished frame follows sooner than a preview is worth
        side.previewed_at = time.monotonic()
        if side.previewed == 0:
            side.propagate_from = (side.job_ms, progress.done)
        try:
            shown = side.job.preview(self.preview_scale)
            if shown:
                side.serial += 1
                textures = side.pipeline.preview_textures
                self._snapshot(side, Stamp(side.serial, False, progress.done, progress.total),
                               side.result, textures)
                display = self.settings_for(state, side.name)
                if side.auto_scale is None and display.auto_exposure:
                    side.auto_scale = picture_scale(side.picture, display.indirect_only)
                status.published = True
        except Exception as exc:  # noqa: BLE001 - the job's own run reports it next
            print(f"lpv-explorer: preview of {side.name} failed: {exc}", file=sys.stderr)
        finally:
            _use_screen(self.ctx)
        side.previewed = progress.done
        elapsed = (time.perf_counter() - began) * 1e3
        side.job_ms += elapsed
        side.previews_ms += elapsed
        side.preview_ms = elapsed
        status.work.append(WorkUnit(side.name, f"preview {progress.done}/{progress.total}",
                                    elapsed))

    def _finish_due_ms(self, side: SideState) -> float:
        """When ``side``'s job should finish, in milliseconds of work from now: its
        propagation steps left at the pace since its first preview, then the gather and
        display as the pipeline last timed them (infinite before a pace is known)."""
        progress = side.progress
        if side.propagate_from is None or progress is None or progress.stage != "propagate":
            return float("inf")
        ms, steps = side.propagate_from
        if progress.done <= steps:
            return float("inf")
        per_step = (side.job_ms - side.previews_ms - ms) / (progress.done - steps)
        timings = side.pipeline.timings_ms
        rest = sum(timings.get(stage, 0.0) for stage in downstream("propagate")[1:])
        return (progress.total - progress.done) * max(per_step, 0.0) + rest

    def _snapshot(self, side: SideState, stamp: Stamp, result: "FrameResult | None",
                  textures: tuple | None = None) -> None:
        """Copy the side's linear buffers (``textures``: a preview's own, e.g. reduced)
        into its picture; a finished frame's fog too (a preview shows the surfaces without
        it, as the pipeline's own preview does)."""
        if side.picture is None:
            side.picture = Picture(self.ctx, self.programs)
        fog = side.pipeline.fog_textures if stamp.final else None
        side.picture.copy_from(*(textures or side.pipeline.linear_textures), stamp, result,
                               fog, getattr(side.pipeline, "surface_textures", None))

    def _finished(self, state: "AppState", side: SideState, status: ControllerStatus) -> None:
        job, request = side.job, side.request
        result = job.result
        side.job, side.request = None, None
        side.done, side.failed, side.result = request, None, result
        side.serial += 1
        began = time.perf_counter()
        self._snapshot(side, Stamp(side.serial, True), result)
        _use_screen(self.ctx)
        status.work.append(WorkUnit(side.name, "snapshot",
                                    (time.perf_counter() - began) * 1e3))
        status.published = True
        side.auto_scale = float(result.display_scale)
        side.scale_cache.clear()
        ran = set(result.stages_run)
        if ran and ran <= CAMERA_STAGES and "gather" in ran:
            self._measure_camera(request, side.job_ms)
        if side.name == "A":
            self._first_done = True     # the first (small) picture is out: full size next
        self._post_warnings(state, side, result)
        rt = state.runtime
        if side.name == "A":
            rt.frame.pipeline_error = None
            if not request.interactive:
                self.ran_settings = state.settings
                self.failed_settings = None
            s = request.settings
            self._good_scene = (s.scene, s.camera, s.light, s.light_flux)
            self._scene_defaults(state, side.pipeline, s.scene)
        rt.frame.pipeline_ms = side.job_ms

    def _measure_camera(self, request: Request, elapsed_ms: float) -> None:
        """Choose the drag scale from the camera-only frames timed so far: the largest of
        DRAG_SCALES whose frame fits the drag budget (shared by the sides on screen). A
        scale not timed yet is predicted from the time per pixel of the nearest one."""
        pixels = request.settings.width * request.settings.height
        full = max(self.full_pixels, 1)
        scale = min(DRAG_SCALES, key=lambda k: abs(k * k * full - pixels))
        self.camera_ms[scale] = elapsed_ms
        self.camera_ms_per_pixel = elapsed_ms / max(pixels, 1)

        def predicted(k: float) -> float:
            if k in self.camera_ms:
                return self.camera_ms[k]
            nearest = min(self.camera_ms, key=lambda m: abs(m - k))
            return self.camera_ms[nearest] * (k / nearest) ** 2

        fits = [k for k in DRAG_SCALES if predicted(k) <= self._side_budget_ms]
        self.drag_scale = fits[0] if fits else DRAG_SCALES[-1]

    # ------------------------------------------------------------------ display
    def side_display(self, state: "AppState", side: str) -> SideDisplay:
        """How ``side`` is shown (explorer/ui/side_display.py ``side_display``)."""
        return side_display(state, self.sides, side, self.settings_for(state, side))

    # ------------------------------------------------------------------ runtime
    def _publish_runtime(self, state: "AppState") -> None:
        rt = state.runtime
        a, b = self.sides["A"], self.sides["B"]
        rt.frame.result = a.result
        rt.frame.compare_result = b.result if state.comparing else None
        rt.frame.frame_view = a.pipeline.view if a.pipeline is not None and a.result is not None \
            else None
        rt.frame.pictures = {name: side.picture for name, side in self.sides.items()
                             if side.picture is not None and side.picture.ready}
        update_side_exposures(state, {name: side.result for name, side in self.sides.items()},
                              {name: self.settings_for(state, name).indirect_only
                               for name in self.sides})

    @property
    def busy(self) -> bool:
        return any(side.job is not None for side in self.sides.values())

    def stage_runs(self, side: str = "A") -> Counter:
        return self.sides[side].stage_runs

    # ------------------------------------------------------------------ failures
    def _failed(self, state: "AppState", side: SideState, request: Request | None,
                exc: Exception) -> None:
        side.failed = request
        self._status.failures += 1
        if side.name == "A":
            self.failed_settings = state.settings
        rt = state.runtime
        settings = request.settings if request is not None else state.settings
        text = f"{type(exc).__name__}: {exc}"
        default_scene = Settings().scene
        if self._good_scene is None and settings.scene != default_scene and side.name == "A":
            # The scene saved last time (a mesh since moved, say) cannot open: start from
            # the default scene rather than an empty view.
            self._good_scene = (default_scene, None, None, None)
        if self._good_scene is not None and settings.scene != self._good_scene[0]:
            if side.name == "A":
                # A mesh that fails to load: say so and keep the previous scene.
                scene, camera, light, flux = self._good_scene
                state.notify(f"could not open {settings.scene}: {exc}", "error")
                state.update(scene=scene, camera=camera, light=light, light_flux=flux)
                print(f"lpv-explorer: could not open {settings.scene}: {exc}",
                      file=sys.stderr)
            return
        rt.frame.pipeline_error = f"pipeline {side.name} failed: {text}"
        state.notify(rt.frame.pipeline_error, "error")
        print(f"lpv-explorer: {rt.frame.pipeline_error}", file=sys.stderr)
        traceback.print_exception(exc, file=sys.stderr)

    def failed_request(self, side: str = "A") -> Request | None:
        return self.sides[side].failed

    def _post_warnings(self, state: "AppState", side: SideState,
                       result: "FrameResult") -> None:
        """The numeric guards' warnings of a new result in the Messages panel: each one
        the side's previous result did not have, once."""
        warnings = tuple(result.warnings)
        for text in warnings:
            if text not in side.warned:
                state.notify(text if side.name == "A" else f"B: {text}", "warning")
        side.warned = warnings

    def _scene_defaults(self, state: "AppState", pipeline, scene_name: str) -> None:
        """The scene as loaded (``runtime.scene_facts.scene``: its lights, objects and paths for the
        Lights & objects panel) and its own camera and primary light (before any
        override), so orbiting and the light sliders start from what is shown. Loaded
        once per scene."""
        rt = state.runtime
        if self._defaults_for == scene_name:
            return
        self._defaults_for = scene_name
        scene = pipeline.base_scene
        if scene is None:
            try:
                from explorer.scene import load_scene

                scene = load_scene(scene_name)
            except Exception:  # noqa: BLE001 - defaults are a convenience
                scene = None
        rt.scene_facts.scene = None if scene is None else (scene_name, scene)
        if getattr(scene, "notice", ""):       # e.g. where a light was put in a closed mesh
            state.notify(scene.notice)
        from explorer.scene import SpotLight

        rt.scene_facts.camera_default = eye_target(scene.camera if scene is not None else None)
        light = None
        if scene is not None:
            try:     # the primary light of the lights that shine (Settings.lights)
                light = scene.with_lights(state.settings.lights).light
            except Exception:  # noqa: BLE001 - lights the scene does not have
                light = scene.light
        rt.scene_facts.light_default = eye_target(light)
        rt.scene_facts.light_flux_default = light.flux if light is not None else None
        facts = rt.scene_facts
        facts.light_is_spot = isinstance(light, SpotLight)
        facts.light_cone_default = light.cone_degrees if facts.light_is_spot else None

    # ------------------------------------------------------------------ shaders, tasks
    def _hot_reload(self, state: "AppState", now: float | None = None) -> None:
        """Recompile shaders whose files changed (polled every SHADER_POLL_S): a failed
        compile keeps the last good program and records its log in
        ``runtime.services.shader_errors``; a side whose programs changed renders again."""
        now = time.monotonic() if now is None else now
        if now - self._shader_poll < SHADER_POLL_S:
            return
        self._shader_poll = now
        errors: dict[str, str] = {}
        for side in self.sides.values():
            if side.pipeline is None:
                continue
            if side.pipeline.reload_shaders():
                side.done = None
                state.notify(f"shaders reloaded ({side.name})")
            errors.update(side.pipeline.programs.errors)
        self.programs.reload_if_changed()
        errors.update(self.programs.errors)
        state.runtime.services.shader_errors = errors
        self._reload_scene(state)

    def _reload_scene(self, state: "AppState") -> None:
        """The scene on screen edited on disk (explorer/ui/scene_watch.py): read it again
        and show it; an edit that does not load keeps the scene as it was and says why."""
        shown = state.runtime.scene_facts.scene
        if shown is None:
            return
        name, scene = shown
        if self.scene_watch.name != name:
            self.scene_watch.watch(name, scene.files)
            return
        if not self.scene_watch.changed():
            return
        from explorer.scene import load_scene

        try:
            edited = load_scene(name)
        except Exception as exc:  # noqa: BLE001 - the user's edit, said in the window
            state.notify(f"{name} changed but does not load ({exc}); the scene shown is "
                         f"the one read before", "error")
            return
        for side in self.sides.values():
            if side.pipeline is not None and side.pipeline.settings.scene == name:
                side.pipeline.reload_scene(edited)
                side.job, side.request, side.done, side.failed = None, None, None, None
        self._defaults_for = None          # its camera and light defaults anew
        state.runtime.scene_facts.scene = (name, edited)
        self.scene_watch.watch(name, edited.files)
        state.notify(f"{name} changed on disk: reloaded")

    def poll_shaders(self, state: "AppState") -> None:
        """Check the shader files now (the next update reloads what changed)."""
        self._shader_poll = 0.0
        self._hot_reload(state)

    def _tasks(self, state: "AppState", left_ms: float, status: ControllerStatus) -> None:
        """The panels' background GPU work (``runtime.services.tasks``) in what is left of the
        budget, shared by the tasks that have work (an idle one is still called: it may
        start some, e.g. the Error panel's measurement of a new configuration)."""
        tasks = state.runtime.services.tasks
        if not tasks or left_ms < MIN_TASK_MS:
            return
        share = left_ms / max(sum(bool(task.running) for task in tasks), 1)
        for task in list(tasks):
            began = time.perf_counter()
            try:
                task.advance(self.ctx, share / 1e3)
            except Exception as exc:  # noqa: BLE001 - shown in the window, the app goes on
                state.notify(f"{type(task).__name__} failed: {exc}", "error")
                traceback.print_exception(exc, file=sys.stderr)
                task.release()
                tasks.remove(task)
            finally:
                _use_screen(self.ctx)
            if task.running:
                status.work.append(WorkUnit("task", type(task).__name__,
                                            (time.perf_counter() - began) * 1e3))

    def release(self) -> None:
        for side in self.sides.values():
            if side.picture is not None:
                side.picture.release()
            if side.pipeline is not None:
                side.pipeline.release()
        self.sides = {name: SideState(name) for name in SIDES}
        self.programs.release()


def keeps_steps(state: "AppState", side: str) -> bool:
    """Whether ``side``'s frame keeps grid_0..grid_N of every cascade: the in-scene
    overlays show the light in flight (drawn over both sides of a split view; a lesson's
    ``[steps.show]`` sets them), or the Inspect panel steps through A's propagation."""
    return state.overlays.needs_steps or (side == "A"
                                          and state.inspect.source == "propagation")


class _Budget:
    """One update's time: ``ms`` from ``start``, back to ``base_ms`` once
    ``input_pending()`` says input arrived (asked only while more than the base is left
    to spend)."""

    def __init__(self, start: float, ms: float, base_ms: float,
                 input_pending: Callable[[], bool] | None) -> None:
        self.start, self.ms, self.base_ms = start, ms, base_ms
        self.input_pending = input_pending

    def left(self) -> float:
        """Milliseconds left (negative once overspent)."""
        if self.ms > self.base_ms and self.input_pending is not None and self.input_pending():
            self.ms = self.base_ms
        return self.ms - (time.perf_counter() - self.start) * 1e3

    def base_left(self) -> float:
        """Milliseconds left of the frame budget alone."""
        return self.base_ms - (time.perf_counter() - self.start) * 1e3


class _StageCounter:
    """A job's progress callback that counts each stage once when it starts."""

    def __init__(self, counts: Counter) -> None:
        self.counts = counts
        self.last: str | None = None

    def __call__(self, stage: str, done: int, total: int) -> None:
        if stage != self.last:
            self.last = stage
            self.counts.update([stage])


def eye_target(value) -> tuple | None:
    """(eye, target) from a camera/light object or pair, or None."""
    if value is None:
        return None
    for eye_name, target_name in (("eye", "target"), ("position", "target")):
        if hasattr(value, eye_name) and hasattr(value, target_name):
            eye, target = getattr(value, eye_name), getattr(value, target_name)
            if callable(eye):   # DirectionalLight.eye(bounds) is a method: use position
                continue
            return (tuple(float(v) for v in eye), tuple(float(v) for v in target))
    try:
        eye, target = value
        return (tuple(float(v) for v in eye), tuple(float(v) for v in target))
    except (TypeError, ValueError):
        return None


def _use_screen(ctx) -> None:
    """Bind the window's framebuffer again after offscreen work (a headless context has
    none)."""
    if ctx.screen is not None:
        ctx.screen.use()
