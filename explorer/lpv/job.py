"""A frame in progress: the pipeline's work split into units that fit a frame budget.

:meth:`explorer.lpv.pipeline.Pipeline.start` makes a :class:`Job`; each
:meth:`Job.advance` does whole units of work (a stage, one cascade of the injection or
the geometry volume or, for a large grid, each of its draws and copies, a slab of a
propagation step, a band of the gather) until its time
budget is spent, choosing the next unit only when its measured time still fits (at least
one unit per call), and returns a :class:`Progress`. The stages run in
:data:`explorer.lpv.stage_list.EXECUTION_ORDER`; a stage whose key has not changed since its
last completed run is skipped.

Starting another job cancels this one: the stage it was in the middle of is discarded
(its key was forgotten when it started, so it runs again), the completed ones are kept.
An exception (a KeyboardInterrupt too) leaves the pipeline in the same consistent state
and propagates.

A unit that issues read-backs yields a :class:`~explorer.gl.gpu_sync.GpuWait`: within a
budget the job does the next unit (which takes the arrays) only once the copies are done
(:attr:`Job.gpu_pending`; the window then does it in a later frame, with no wait), while
a job run to its end at once (``advance(None)``) waits for exactly those copies.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

from explorer.gl.gpu_sync import GpuWait
from explorer.lpv.audit import audit_mode
from explorer.lpv.cache_keys import downstream, remembered_stage_key
from explorer.lpv.stage_list import DECLARATIONS, EXECUTION_ORDER, PIXEL_STAGES, STAGES, VERBS

if TYPE_CHECKING:
    from explorer.lpv.frame import FrameResult
    from explorer.lpv.settings import Settings
    from explorer.lpv.vpl import VplArrays

FINAL_STAGE = EXECUTION_ORDER[-1]
"""The stage whose last unit finishes a job (the display): the frame that runs it shows the
finished frame, which costs its drawing more (``advance``'s ``finishing_ms``)."""

GRID_STAGES = tuple(name for name in downstream("grid")
                    if name not in PIXEL_STAGES and not DECLARATIONS[name].by_value)
"""The stages whose work grows with the grid's cells (all cascades' together): their next
unit is estimated at the grid's size as a per-pixel stage's is at the image's
(:meth:`Job.next_unit_ms`), so that the first 64³ job after 32³ ones is not sized by the
32³ units."""

_STAGE_ORDER = {name: i for i, name in enumerate(STAGES)}
"""Each stage's place in the declared order (what ``Progress.stages_run`` is sorted by)."""

ProgressCallback = Callable[[str, int, int], None]
"""``progress(stage, done, total)``: called when a stage starts (done 0) and after each of
its units."""


class Pipeline(Protocol):
    """What a job calls on the pipeline that made it
    (:class:`explorer.lpv.pipeline.Pipeline`, its "what a Job calls" section); named
    here so that this module does not import the pipeline, which imports it."""

    keys: dict[str, object]
    out_keys: dict[str, object]
    unit_ms: dict[str, float]
    unit_ms_at: dict[tuple[str, int], float]
    unit_ms_sized: dict[tuple[str, int, int], float]
    unit_pixels: dict[str, int]
    key_memo: dict[str, tuple]
    job: Job | None

    def extra_input(self, stage: str, job: Job) -> object: ...
    def satisfied(self, stage: str, job: Job) -> bool: ...
    def evaluate(self, stage: str, job: Job) -> object: ...
    def stage_units(self, stage: str, job: Job) -> int: ...
    def stage_work(self, stage: str, job: Job) -> Iterator[int | None]: ...
    def finish_job(self, job: Job) -> FrameResult: ...
    def show_preview(self, job: Job, scale: float = ..., injected: bool = ...) -> bool: ...

@dataclass(frozen=True)
class Progress:
    """Where a job stands after :meth:`Job.advance`."""

    stage: str | None
    """The stage in progress, None once the job is finished."""
    done: int
    """Units of that stage done (propagation: steps, all cascades together; a large grid's
    step takes several units, its slabs)."""
    total: int
    finished: bool
    stages_run: tuple[str, ...]
    """The stages completed so far, in the declared order
    (:data:`explorer.lpv.stage_list.STAGES`)."""

    @property
    def label(self) -> str:
        """A short line for the window, e.g. ``"propagating 5/8"``."""
        if self.finished:
            return "done"
        if self.stage is None:
            return "waiting"
        verb = VERBS.get(self.stage, self.stage)
        return f"{verb} {self.done}/{self.total}" if self.total > 1 else verb


class Job:
    """The work of one frame (module docstring). Made by :meth:`Pipeline.start`."""

    def __init__(self, pipeline: Pipeline, settings: Settings, keep_steps: bool,
                 need_audit: str | bool, vpls: VplArrays | None,
                 progress: ProgressCallback | None) -> None:
        self.pipeline = pipeline
        self.settings = settings
        self.keep_steps = bool(keep_steps)
        self.need_audit = audit_mode(need_audit)
        """The audit mode asked for (:data:`explorer.lpv.audit.AUDIT_MODES`)."""
        self.vpls = vpls
        self.vpls_key = None if vpls is None else vpls.digest()
        self.progress_callback = progress
        self._index = 0
        self._work: Iterator[int | None] | None = None
        self._stage: str | None = None
        self._key: tuple | None = None
        self._done = 0
        self._total = 0
        self._unit = 0
        self._gpu_wait: GpuWait | None = None
        """What the last unit yielded when its next unit reads back GPU work."""
        """Units of the current stage run so far."""
        self.out_keys: dict[str, object] = {}
        """Output key of every stage evaluated so far (run or up to date)."""
        self._ran: list[str] = []
        self._result: FrameResult | None = None
        self.cancelled = False
        self.unit_budget_ms: float | None = None
        """What is left of the budget of the :meth:`advance` call running the unit in
        progress (None: no budget), for a stage that sizes its units itself (the
        propagation groups small steps)."""

    # ------------------------------------------------------------------ state
    def asks_for(self, settings: Settings, keep_steps: bool, need_audit: str | bool,
                 vpls: VplArrays | None) -> bool:
        """Whether this unfinished job computes the frame these arguments ask for."""
        if self.done or self.cancelled or settings != self.settings:
            return False
        vpls_key = None if vpls is None else vpls.digest()
        return (bool(keep_steps), audit_mode(need_audit), vpls_key) == (
            self.keep_steps, self.need_audit, self.vpls_key)

    @property
    def done(self) -> bool:
        return self._result is not None

    @property
    def result(self) -> FrameResult:
        if self._result is None:
            raise RuntimeError("the job has not finished: advance() until job.done")
        return self._result

    @property
    def stage(self) -> str | None:
        """The stage in progress (None between stages and once finished)."""
        return self._stage

    def evaluated(self, stage: str) -> bool:
        """Whether ``stage`` is complete (ran or was up to date) in this job."""
        return stage in self.out_keys

    @property
    def progress(self) -> Progress:
        return Progress(self._stage, self._done, self._total, self.done,
                        tuple(sorted(self._ran, key=_STAGE_ORDER.__getitem__)))

    # ------------------------------------------------------------------ work
    def advance(self, budget_ms: float | None = None,
                finishing_ms: float | None = None,
                until: Callable[[], bool] | None = None) -> Progress:
        """Do whole units of work until ``budget_ms`` milliseconds are spent (None: until
        the frame is finished); at least one unit per call. ``finishing_ms``: the units of
        :data:`FINAL_STAGE` keep to this much of the call instead (when less), so that the
        frame showing the finished frame leaves its extra drawing room: a unit of it that
        does not fit waits for the next call, as any unit over the budget does.
        ``until``: asked after each unit (once the next stage, if any, has begun); True ends
        the call there (the window's first picture of a job is taken as soon as there is
        one: :meth:`preview_source`)."""
        if self.cancelled:
            raise RuntimeError("the job was cancelled (another job started)")
        start = time.perf_counter()
        worked = False
        while self._result is None:
            if self._work is None and not self._begin_next():
                continue
            if until is not None and worked and until():
                break       # (after the next stage began: next_unit_ms is its own unit's)
            if budget_ms is not None and self.gpu_pending:
                break               # the next unit reads back what the GPU still copies
            spent = (time.perf_counter() - start) * 1e3
            limit = budget_ms
            if limit is not None and finishing_ms is not None and self._stage == FINAL_STAGE:
                limit = min(limit, finishing_ms)
            if limit is not None and worked and spent + self.next_unit_ms() > limit:
                break
            self.unit_budget_ms = None if limit is None else max(limit - spent, 0.0)
            self._run_unit()
            worked = True
        return self.progress

    @property
    def gpu_pending(self) -> bool:
        """The next unit reads back GPU work that is not done yet (module docstring)."""
        return self._gpu_wait is not None and not self._gpu_wait.ready()

    def next_unit_ms(self) -> float:
        """What the next unit of work should take, as measured: the same unit of the
        stage's last run (``Pipeline.unit_ms_at``), else the stage's last unit, else 0. A
        stage whose work grows with the pixels (``PIXEL_STAGES``) or the grid's cells
        (:data:`GRID_STAGES`) takes the same unit at this size (``Pipeline.unit_ms_sized``);
        at a size not measured yet, one measured at a smaller size is scaled up by the
        pixels or the cells (never down: a band of rows holds as many pixels at any size),
        so that the full-size frame after a drag's reduced ones is not sized by the
        reduced units, nor a 64³ grid's start by a 32³ one's."""
        pipeline = self.pipeline
        stage = self._stage or ""
        unit_ms = pipeline.unit_ms.get(stage, 0.0)
        estimate = pipeline.unit_ms_at.get((stage, self._unit), unit_ms)
        size = self.size_of(stage)
        if size is None:
            return estimate
        exact = pipeline.unit_ms_sized.get((stage, self._unit, size))
        if exact is not None:
            return exact
        measured_at = pipeline.unit_pixels.get(stage)
        if not measured_at:
            return estimate
        return estimate * max(size / measured_at, 1.0)

    def next_unit_measured(self) -> bool:
        """Whether :meth:`next_unit_ms` is a measure of the same unit (at this size, for a
        stage whose work grows with the pixels or the cells), not a scaled or borrowed
        one: the first 64³ propagation's start, estimated from a 32³ one's, takes 5–10×
        more (its grids made anew)."""
        pipeline, stage = self.pipeline, self._stage or ""
        size = self.size_of(stage)
        if size is None:
            return (stage, self._unit) in pipeline.unit_ms_at
        return (stage, self._unit, size) in pipeline.unit_ms_sized

    @property
    def pixels(self) -> int:
        """The image's pixels (what a per-pixel stage's units grow with)."""
        return int(self.settings.width) * int(self.settings.height)

    def size_of(self, stage: str) -> int | None:
        """What ``stage``'s units grow with: the image's pixels for a per-pixel stage, the
        cells of every cascade for one of :data:`GRID_STAGES` (once the grid is evaluated),
        else None."""
        if stage in PIXEL_STAGES:
            return self.pixels
        if stage in GRID_STAGES:
            specs = self.out_keys.get("grid")
            if isinstance(specs, tuple) and specs:
                return sum(math.prod(spec.cells) for spec in specs)
        return None

    def preview_source(self) -> str | None:
        """What a preview of the job would show now: ``"propagation"``, the accumulation
        (once the propagation has a step, or is complete); ``"injected"``, the injected
        grids alone (acc_0 = grid_0: this job ran the injection and the propagation has
        no step yet); None before the G-buffer and the RSM, before either, or once the
        job is finished."""
        if self.done or not (self.evaluated("gbuffer") and self.evaluated("rsm")):
            return None
        if (self._stage == "propagate" and self._done > 0) or self.evaluated("propagate"):
            return "propagation"
        if self.evaluated("inject") and "inject" in self._ran:
            return "injected"
        return None

    def preview(self, scale: float = 1.0, injected: bool = False) -> bool:
        """Gather and display the accumulation so far into ``Pipeline.final_texture`` (the
        view then shows the light growing step by step); False when there is nothing to
        show yet (before the G-buffer, the RSM or the first propagation step) or when the
        job is finished (``final_texture`` then holds the frame). ``scale`` < 1: a reduced
        linear picture in ``Pipeline.preview_textures`` instead (no display pass).
        ``injected``: before the first step, the injected grids' picture when this job
        ran the injection (:meth:`preview_source` ``"injected"``: the light before any
        propagation, a partial picture)."""
        source = self.preview_source()
        if source is None or (source == "injected" and not injected):
            return False
        return self.pipeline.show_preview(self, scale, injected=source == "injected")

    def cancel(self) -> None:
        """Stop here; a stage in the middle of its work runs again in the next job."""
        self._abandon()

    # ------------------------------------------------------------------ stages
    def _begin_next(self) -> bool:
        """Evaluate the next stage: skip it when up to date, else start its work (True).
        Finishes the job after the last stage."""
        if self._index == len(EXECUTION_ORDER):
            self._result = self.pipeline.finish_job(self)
            self._stage = None
            if self.pipeline.job is self:
                self.pipeline.job = None
            return False
        name = EXECUTION_ORDER[self._index]
        pipeline = self.pipeline
        key = remembered_stage_key(pipeline.key_memo, self.settings, name, self.out_keys,
                                   pipeline.extra_input(name, self))
        if DECLARATIONS[name].by_value:
            value = pipeline.evaluate(name, self)
            last = pipeline.out_keys.get(name)
            if last != value or pipeline.keys.get(name) is None:
                self._ran.append(name)
            if last == value:
                value = last    # the same object: the keys downstream are remembered
            pipeline.keys[name], pipeline.out_keys[name] = key, value
            self._complete(name, value, ran=False)
            return False
        if pipeline.keys.get(name) == key and pipeline.satisfied(name, self):
            self._complete(name, key, ran=False)
            return False
        pipeline.keys.pop(name, None)      # its outputs are about to be overwritten
        self._stage, self._key, self._done, self._unit = name, key, 0, 0
        self._total = pipeline.stage_units(name, self)
        self._work = pipeline.stage_work(name, self)
        self._report()
        return True

    def _run_unit(self) -> None:
        name = self._stage
        started = time.perf_counter()
        try:
            self._gpu_wait = None
            try:
                count = next(self._work)
                finished = False
            except StopIteration:
                count, finished = self._total, True
            if isinstance(count, GpuWait):
                self._gpu_wait, count = count, count.progress
            elapsed = (time.perf_counter() - started) * 1e3
            pipeline = self.pipeline
            pipeline.unit_ms[name] = elapsed
            pipeline.unit_ms_at[(name, self._unit)] = elapsed
            size = self.size_of(name)
            if size is not None:
                pipeline.unit_ms_sized[(name, self._unit, size)] = elapsed
                pipeline.unit_pixels[name] = size
            self._unit += 1
            self._done = self._done + 1 if count is None else count
            if finished:
                self.pipeline.keys[name] = self._key
            if self.progress_callback is not None:
                self._report()
        except BaseException:
            # an unfinished stage keeps its key forgotten: it runs again next time
            self._abandon()
            raise
        if finished:
            self._work = None
            self._complete(name, self._key, ran=True)

    def _abandon(self) -> None:
        if self._work is not None:
            self._work.close()
        self._work, self._stage = None, None
        self.cancelled = True
        if self.pipeline.job is self:
            self.pipeline.job = None

    def _complete(self, name: str, out_key: object, ran: bool) -> None:
        self.out_keys[name] = out_key
        if ran:
            self._ran.append(name)
        self._stage = None
        self._index += 1

    def _report(self) -> None:
        if self.progress_callback is not None and self._stage is not None:
            self.progress_callback(self._stage, self._done, self._total)
