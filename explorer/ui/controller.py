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
  the pixels: quick to gather and to copy; a job's first at ``FIRST_PREVIEW_SCALE``, also
  while a change that only the gather sees is gathered), copied into the side's
  :class:`~explorer.ui.picture.Picture`, paced by explorer/ui/previews.py and taken by
  explorer/ui/preview_taking.py;
* gives the pipelines more of each frame while the user leaves the window alone (the
  quiet budget of explorer/ui/frame_budget.py; the shell's ``input_pending`` is asked
  between units, and input drops the frame back to the budget at once; the background
  tasks, explorer/ui/panel_tasks.py, keep to the frame budget);
* runs no stage for a display-only change: the pipeline's Settings have the display
  stage's fields pinned (:data:`PINNED_DISPLAY`), and exposure, tone curve, indirect
  only and the auto exposure of each side are the view composer's
  (:meth:`side_display`, explorer/ui/view_composer.py);
* renders at a reduced size while the camera is dragged (``interacting``): the largest
  of ``frame_budget.DRAG_SCALES`` whose camera-dependent work (G-buffer, gather,
  display) fits the frame budget as last measured, and at the full size once the drag ends;
* keeps the last good result when a request fails (one message per failure; a scene
  that does not open restores the previous one), reloads changed shaders and the edited
  scene (explorer/ui/scene_reload.py), and advances the panels' background
  tasks (``runtime.services.tasks``, the Error panel's reference) in what is left of the budget;
* refuses in one message a side whose Settings A's rest cannot run with, and releases
  what sides B, C and D made once the view has not shown them for :data:`IDLE_RELEASE_S`.
"""

from __future__ import annotations

import sys
import time
import traceback
from collections import Counter
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING

from explorer.gl.context import use_screen
from explorer.lpv.audit import audit_mode
from explorer.lpv.job import FINAL_STAGE
from explorer.lpv.settings import Settings
from explorer.lpv.stage_list import PIXEL_STAGES
from explorer.schema import stages_reading
from explorer.ui import previews
from explorer.ui.controller_state import (
    ControllerStatus,
    Request,
    SideState,
    StageCounter,
    WorkUnit,
    keeps_steps,
)
from explorer.ui.frame_budget import (
    FINISHING_STAGES,
    QUIET_BUDGET_MS,
    DragSizer,
    FrameBudget,
    ResultDrawing,
)
from explorer.ui.lesson_watch import LessonWatch
from explorer.ui.panel_tasks import run_tasks
from explorer.ui.picture import SideDisplay, Stamp
from explorer.ui.preview_taking import snapshot, take_preview_if_due
from explorer.ui.previews import (
    FIRST_PREVIEW_SCALE,
    INJECTED_PREVIEW_CELLS,
    PREVIEW_INTERVAL_S,
    PREVIEW_SCALE,
)
from explorer.ui.scene_reload import Reloads
from explorer.ui.scene_watch import SceneWatch
from explorer.ui.side_display import (
    ALL_SIDES,
    SIDES,
    VARIANT_SIDES,
    side_display,
    side_settings,
    update_side_exposures,
)

if TYPE_CHECKING:
    import moderngl

    from explorer.lpv.frame import FrameResult
    from explorer.ui.scene_watch import SceneWatch
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
FIRST_PICTURE_SCALE = 0.25
"""The first picture after launch renders at this fraction of the size (quick to show),
then the full size follows."""
MIN_RENDER_EDGE = 16


SHOWN_STEP_LEVELS = 1
"""Cascade levels whose propagation steps a side's frame keeps when shown: the finest
only (the in-flight overlays, the Inspect panel, the picked cell's steps and the lesson
figures read level 0's; the other levels' would double the steps at two cascades)."""
IDLE_RELEASE_S = 20.0
"""Seconds a side the view stopped showing keeps what it made: a quick look back at the
split view costs nothing, a comparison left for good gives its memory back."""


class PipelineController:
    """Owns the pipelines of sides A and B (module docstring)."""

    def __init__(self, ctx: moderngl.Context, pipeline_class: Callable | None) -> None:
        from explorer.gl.program import ProgramCache

        self.ctx = ctx
        self.pipeline_class = pipeline_class
        self.programs = ProgramCache(ctx)
        """The pictures' copy program (the pipelines have their own caches)."""
        self.sides: dict[str, SideState] = {name: SideState(name) for name in ALL_SIDES}
        self.drag = DragSizer()
        """The render size of a camera drag, from the camera frames measured."""
        self.preview_interval_s = PREVIEW_INTERVAL_S
        """The shortest time between two previews of a job (0: after every step, and
        to the end)."""
        self.preview_scale = PREVIEW_SCALE
        """Fraction of each edge a progressive preview gathers (1: the full size)."""
        self.first_preview_scale = FIRST_PREVIEW_SCALE
        """Fraction of each edge a job's first preview gathers (at most
        :attr:`preview_scale`)."""
        self.injected_preview_cells = INJECTED_PREVIEW_CELLS
        """A job that ran the injection on grids of this many cells or more (all cascades)
        shows the injected light as its first preview (explorer/ui/previews.py)."""
        self.quiet_budget_ms = QUIET_BUDGET_MS
        """A frame's budget once no input came for ``frame_budget.QUIET_AFTER_S`` (at
        least the frame budget; 0: never more than the frame budget)."""
        self.budget_used_ms = 0.0
        """The budget the last update worked to (the frame budget or the quiet one)."""
        self.draw_ms = 0.0
        """What the window spends drawing a frame (the shell's measure)."""
        self.result_drawing = ResultDrawing()
        """What a frame showing a finished frame draws more (the shell notes it): the units
        finishing a job leave it free of the frame budget."""
        self.ran_settings: Settings | None = None
        """state.settings when A last finished a frame."""
        self.failed_settings: Settings | None = None
        """state.settings when A last failed (None once it finishes a frame again)."""
        self._good_scene: tuple | None = None
        self.reloads = Reloads()
        """Shaders and the scene shown, reloaded when their files change."""
        self._turn = 0
        self._first_done = False
        self._interacting = False
        """The update in progress runs while the camera, an object or a held slider moves."""
        self._status = ControllerStatus()
        self._side_budget_ms = 30.0
        self._budget = FrameBudget(0.0, 0.0, 0.0, None)
        self.full_pixels = 0
        """Pixels of the full render size (the state's, each update)."""
        self.idle_release_s = IDLE_RELEASE_S
        """How long a side the view no longer shows keeps its pipeline, picture and frame."""
        self._idle_since: dict[str, float] = {}
        self._requests: dict[str, tuple] = {}
        self._refusals: dict[str, str] = {}
        """Side -> the last reason its Settings were refused (said once)."""
        """Side -> (state.settings, the rest of the inputs, the Request made of them)."""

    # ------------------------------------------------------------------ requests
    def settings_for(self, state: AppState, side: str) -> Settings:
        """The Settings ``side`` shows (explorer/ui/side_display.py ``side_settings``), for
        how it is shown; A's when the side's own are refused with A's rest (it then runs
        nothing new: :meth:`_make_request` raises and :meth:`update` says why)."""
        try:
            return side_settings(state, side)
        except ValueError:
            return state.settings

    def request_for(self, state: AppState, side: str, need_audit: str | bool,
                    interacting: bool) -> Request:
        # the same request as last frame when nothing it is made of changed: the same
        # Settings object (compared by identity: a new one is a change) and the same rest;
        # making it anew validates every field and compares the Settings by value
        rest = (need_audit, interacting, interacting and self.drag_scale, self._first_done,
                keeps_steps(state, side), side == "B" and (
                    state.compare_settings.corrections, tuple(state.compare_overrides)),
                side in VARIANT_SIDES and tuple(state.compare_variants))
        cached = self._requests.get(side)
        if cached is not None and cached[0] is state.settings and cached[1] == rest:
            return cached[2]
        request = self._make_request(state, side, need_audit, interacting)
        self._requests[side] = (state.settings, rest, request)
        return request

    def _make_request(self, state: AppState, side: str, need_audit: str | bool,
                      interacting: bool) -> Request:
        settings = side_settings(state, side).with_changes(**PINNED_DISPLAY)
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

    def active_sides(self, state: AppState) -> tuple[str, ...]:
        """The sides the view shows: A; B too while comparing; small multiples' further
        variants as C and D."""
        if not state.comparing:
            return ("A",)
        if state.view_mode != "small-multiples":
            return SIDES
        return SIDES + VARIANT_SIDES[:len(state.compare_variants)]

    # ------------------------------------------------------------------ the frame
    def update(self, state: AppState, budget_ms: float, *,
               need_audit: str | bool | Mapping[str, str] = "off", interacting: bool = False,
               drag_budget_ms: float | None = None,
               draw_ms: float | None = None, quiet_s: float = 0.0,
               input_pending: Callable[[], bool] | None = None) -> ControllerStatus:
        """Start, advance and publish within ``budget_ms`` milliseconds (module
        docstring); fills ``state.runtime``. ``need_audit``: the audit mode what is
        drawn needs (explorer.lpv.audit.AUDIT_MODES), or per side (``runtime.
        audit_of_sides``). ``drag_budget_ms``: what a frame may spend on the pipelines
        while the camera is dragged (the window's frame time for the drag's frame rate,
        less its own drawing; default ``budget_ms``): the drag scale
        is chosen so that a camera frame fits it, and a drag's frame gets that much.
        ``draw_ms``: what the window spends drawing a frame (paces the previews).
        ``quiet_s``: seconds since the last input; from ``QUIET_AFTER_S`` on, the
        frame gets :attr:`quiet_budget_ms` unless ``input_pending()`` (asked between
        units) says input arrived, which ends it at ``budget_ms``."""
        status = self._status = ControllerStatus()
        if self.pipeline_class is None:
            return status
        if draw_ms is not None:
            self.draw_ms = draw_ms
        self.reloads.poll(state, self.sides, self.programs)
        start = time.perf_counter()
        active = self.active_sides(state)
        drag_budget_ms = budget_ms if drag_budget_ms is None else drag_budget_ms
        self._budget = FrameBudget.for_frame(
            budget_ms, interacting=interacting, drag_budget_ms=drag_budget_ms,
            quiet_s=quiet_s, quiet_budget_ms=self.quiet_budget_ms,
            input_pending=input_pending)
        self._side_budget_ms = drag_budget_ms / len(active)
        self._interacting = interacting
        self.full_pixels = state.settings.width * state.settings.height
        for name in active:
            try:
                audit = (need_audit.get(name, "off") if isinstance(need_audit, Mapping)
                         else need_audit)
                request = self.request_for(state, name, audit, interacting)
            except ValueError as exc:    # B's corrections or a variant refused with A's rest
                self._refused(state, name, exc)
                continue
            self._ask(state, self.sides[name], request)
        self._release_idle(active)
        running = [self.sides[name] for name in active if self.sides[name].job is not None]
        self._advance(state, running, status)
        # the panels' tasks keep to the frame budget: nobody asks for input inside them
        run_tasks(self.ctx, state, min(self._budget.left(), self._budget.base_left()), status)
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

    def _ask(self, state: AppState, side: SideState, request: Request) -> None:
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
                side.pipeline.steps_levels = SHOWN_STEP_LEVELS
            side.job = side.pipeline.start(
                request.settings, keep_steps=request.keep_steps, need_audit=request.need_audit,
                progress=StageCounter(side.stage_runs))
        except Exception as exc:  # noqa: BLE001 - shown in the window, the app goes on
            self._failed(state, side, request, exc)
            return
        finally:
            use_screen(self.ctx)
        side.request, side.previewed, side.previews, side.job_ms = request, 0, 0, 0.0
        side.previews_ms, side.propagate_from = 0.0, None
        side.progress = side.job.progress

    def _advance(self, state: AppState, running: list[SideState],
                 status: ControllerStatus) -> None:
        """Advance the jobs until the budget is spent: the sides take turns (who goes
        first alternates between frames), each given an equal share of what is left; a
        side whose job has more work goes round again while its next unit still fits. At
        most one progressive preview per side and frame, before its first turn (none that
        frame when the preview left too little for its next unit), but a job's first: the
        job stops after the unit that makes it possible (``Job.advance``'s ``until``,
        ``previews.first_preview_due``) and it is taken at once when what it cost last time
        (``SideState.first_preview_ms``) fits the frame budget left, else the side's turn
        ends and it comes first thing in the next frame. With a
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
            if budget.quiet and side.job.stage in FINISHING_STAGES:
                # the job's finished frame is near, and it is drawn: the frame budget
                budget.to_base()
                left = budget.left()
            if side.name in previewed and not self._fits(side, left / (len(order) + 1)):
                continue
            if side.name not in previewed:
                previewed.add(side.name)
                shown = side.previews
                take_preview_if_due(self, state, side, status)
                if status.published:    # this frame is drawn: no quiet budget on top
                    budget.to_base()
                if side.job is None:
                    continue
                left = budget.left()
                if side.previews != shown and not self._fits(side, left / (len(order) + 1)):
                    continue    # the preview took the frame: the next unit waits for the next
            share = max(left, 0.0) / (len(order) + 1)
            if budget.quiet:
                share = min(share, budget.base_ms)
            first = side.previews == 0 and state.progressive
            self._step(state, side, share, status,
                       until=(lambda side=side: self._first_due(state, side))
                       if first else None)
            if first and not self._first_preview_now(state, side, status, len(order) + 1):
                continue
            if side.job is not None and not side.job.gpu_pending:
                order.append(side)      # (a job waiting for its copies goes on next frame)

    def _first_preview_now(self, state: AppState, side: SideState, status: ControllerStatus,
                           sides_left: int) -> bool:
        """After a turn that had no preview of its job yet: the job's first picture when
        the turn stopped at one (``previews.first_preview_due``), in this frame when what it
        cost last time fits the frame budget left (the frame is drawn), else first thing
        in the next frame (a turn's start); after it the turn goes on with a unit timed
        before at this size that fits (``Job.next_unit_measured``). False: the side's turn
        ends this frame."""
        if side.job is None or not self._first_due(state, side):
            return True
        budget = self._budget
        if budget.base_left() < side.first_preview_ms:
            return False
        take_preview_if_due(self, state, side, status)
        if status.published:
            budget.to_base()
        # the frame is drawn: only a unit timed before at this size goes on in it (the
        # first 64³ job's propagation start, sized by a 32³ one's, would overrun it)
        job = side.job
        return (job is not None and job.next_unit_measured()
                and self._fits(side, budget.left() / sides_left))

    def _first_due(self, state: AppState, side: SideState) -> bool:
        return previews.first_preview_due(state, side, self._interacting,
                                          self.injected_preview_cells)

    def _fits(self, side: SideState, left_ms: float) -> bool:
        """Whether the next unit of ``side``'s job, as last measured, fits ``left_ms`` (and,
        in the job's last stage, what finishing it may take: ``Job.advance``)."""
        if side.job.stage == FINAL_STAGE:
            left_ms = min(left_ms, self._budget.finishing_left(self.result_drawing.extra_ms))
        return left_ms > 0.0 and side.job.next_unit_ms() <= left_ms

    def _step(self, state: AppState, side: SideState, budget_ms: float,
              status: ControllerStatus, until: Callable[[], bool] | None = None) -> None:
        """Advance ``side``'s job within ``budget_ms``; ``until``: the job stops after the
        unit for which it says True (a first picture to take)."""
        began = time.perf_counter()
        try:
            side.progress = side.job.advance(budget_ms, finishing_ms=self._budget.finishing_left(
                self.result_drawing.extra_ms), until=until)
        except Exception as exc:  # noqa: BLE001 - shown in the window, the app goes on
            request = side.request
            side.job, side.request = None, None
            self._failed(state, side, request, exc)
            return
        finally:
            use_screen(self.ctx)
        elapsed = (time.perf_counter() - began) * 1e3
        side.job_ms += elapsed
        status.work.append(WorkUnit(side.name, side.progress.label, elapsed))
        if side.job.done:
            self._finished(state, side, status)

    def _finished(self, state: AppState, side: SideState, status: ControllerStatus) -> None:
        job, request = side.job, side.request
        result = job.result
        side.job, side.request = None, None
        side.done, side.failed, side.result = request, None, result
        side.serial += 1
        began = time.perf_counter()
        snapshot(self, side, Stamp(side.serial, True), result)
        use_screen(self.ctx)
        snapshot_ms = (time.perf_counter() - began) * 1e3
        status.work.append(WorkUnit(side.name, "snapshot", snapshot_ms))
        status.published = status.finished = True
        status.snapshot_ms += snapshot_ms
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
            self.reloads.scene_defaults(state, side.pipeline, s.scene)
        rt.frame.pipeline_ms = side.job_ms

    def _measure_camera(self, request: Request, elapsed_ms: float) -> None:
        """Choose the drag scale from this camera-only frame (explorer/ui/frame_budget.py)."""
        settings = request.settings
        self.drag.measure(settings.width * settings.height, self.full_pixels, elapsed_ms,
                          self._side_budget_ms)

    @property
    def interacting(self) -> bool:
        """Whether the user was dragging (camera, object, slider) at the last update."""
        return self._interacting

    @property
    def drag_scale(self) -> float:
        """The render-size factor of the next camera drag."""
        return self.drag.scale

    # ------------------------------------------------------------------ display
    def side_display(self, state: AppState, side: str) -> SideDisplay:
        """How ``side`` is shown (explorer/ui/side_display.py ``side_display``)."""
        return side_display(state, self.sides, side, self.settings_for(state, side))

    # ------------------------------------------------------------------ runtime
    def _publish_runtime(self, state: AppState) -> None:
        rt = state.runtime
        a, b = self.sides["A"], self.sides["B"]
        rt.frame.result = a.result
        rt.frame.compare_result = b.result if state.comparing else None
        rt.frame.frame_view = a.pipeline.view if a.pipeline is not None and a.result is not None \
            else None
        rt.frame.pictures = {name: side.picture for name, side in self.sides.items()
                             if side.picture is not None and side.picture.ready}
        update_side_exposures(state, {name: side.result for name, side in self.sides.items()},
                              lambda name: self.settings_for(state, name).indirect_only)

    @property
    def busy(self) -> bool:
        return any(side.job is not None for side in self.sides.values())

    def stage_runs(self, side: str = "A") -> Counter:
        return self.sides[side].stage_runs

    # ------------------------------------------------------------------ failures
    def _failed(self, state: AppState, side: SideState, request: Request | None,
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

    def _refused(self, state: AppState, side: str, exc: ValueError) -> None:
        """Side ``side``'s Settings cannot be made from A's (A switched to 26 neighbours
        while B keeps in-place propagation, say): the side shows nothing new and the
        window says why, once per reason."""
        text = f"configuration {side} cannot run with A's settings: {exc}"
        if self._refusals.get(side) != text:
            self._refusals[side] = text
            state.notify(text, "error")

    def failed_request(self, side: str = "A") -> Request | None:
        return self.sides[side].failed

    def _post_warnings(self, state: AppState, side: SideState,
                       result: FrameResult) -> None:
        """The numeric guards' warnings of a new result in the Messages panel: each one
        the side's previous result did not have, once."""
        warnings = tuple(result.warnings)
        for text in warnings:
            if text not in side.warned:
                state.notify(text if side.name == "A" else f"B: {text}", "warning")
        side.warned = warnings

    # ------------------------------------------------------------------ files
    @property
    def scene_watch(self) -> SceneWatch:
        """The files of the scene on screen (explorer/ui/scene_reload.py)."""
        return self.reloads.scene_watch

    @property
    def lesson_watch(self) -> LessonWatch:
        """The file of the lesson being read (explorer/ui/lesson_watch.py)."""
        return self.reloads.lesson_watch

    def poll_shaders(self, state: AppState) -> None:
        """Check the shader and scene files now."""
        self.reloads.poll_now(state, self.sides, self.programs)

    def _release_idle(self, active: tuple[str, ...]) -> None:
        """Sides B, C and D the view has not shown for :attr:`idle_release_s`: their
        pipeline's targets, picture and last frame released (at 64³ with two cascades a
        side holds hundreds of MiB; on llvmpipe GL memory is the process's); shown again,
        a side starts from nothing."""
        now = time.monotonic()
        for name, side in self.sides.items():
            if name in active or name == "A":
                self._idle_since.pop(name, None)
                continue
            if side.pipeline is None and side.picture is None and side.result is None:
                continue
            since = self._idle_since.setdefault(name, now)
            if now - since < self.idle_release_s:
                continue
            if side.job is not None:
                side.job.cancel()
            if side.picture is not None:
                side.picture.release()
            if side.pipeline is not None:
                side.pipeline.release()
            self.sides[name] = SideState(name)
            self._requests.pop(name, None)
            self._refusals.pop(name, None)
            self._idle_since.pop(name, None)

    def release(self) -> None:
        for side in self.sides.values():
            if side.picture is not None:
                side.picture.release()
            if side.pipeline is not None:
                side.pipeline.release()
        self.sides = {name: SideState(name) for name in ALL_SIDES}
        self._requests.clear()
        self.programs.release()
