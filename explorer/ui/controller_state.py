"""What the window's pipeline controller holds per side and reports per frame: the
requests it makes of a pipeline, each side's job and results, the frame's status, and the
pipeline interface it calls (explorer/ui/controller.py)."""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Protocol

import numpy as np

from explorer.lpv.audit import audit_covers
from explorer.lpv.settings import Settings
from explorer.ui.picture import Picture

if TYPE_CHECKING:
    from explorer.gl.program import ProgramCache
    from explorer.lpv.frame import FrameResult
    from explorer.lpv.job import Job, Progress
    from explorer.scene import Scene
    from explorer.ui.state import AppState


class PipelineLike(Protocol):
    """What the controller calls and reads on a pipeline (explorer.lpv.pipeline.Pipeline):
    all of it, so that no call needs a fallback."""

    programs: ProgramCache
    settings: Settings
    """The settings of the last job started."""
    unit_ms: dict[str, float]
    """Stage -> milliseconds of its last unit of work (what fits a budget)."""
    unit_ms_at: dict[tuple[str, int], float]
    """(stage, unit number) -> milliseconds it last took (``Job.next_unit_ms``)."""
    preview_textures: tuple | None
    """The last reduced preview's linear textures (``Job.preview`` with a scale < 1)."""
    steps_levels: int | None
    """How many cascade levels, finest first, keep their steps (``keep_steps``)."""

    def start(self, settings: Settings, keep_steps: bool = ..., need_audit: str | bool = ...,
              progress: Callable[[str, int, int], None] | None = ...) -> Job: ...
    def reload_shaders(self) -> bool: ...
    def reload_scene(self, scene: Scene) -> None: ...
    def release(self) -> None: ...
    def view(self, name: str, **options) -> np.ndarray: ...
    @property
    def timings_ms(self) -> dict[str, float]: ...
    @property
    def linear_textures(self) -> tuple: ...
    @property
    def fog_textures(self) -> tuple | None: ...
    @property
    def base_scene(self) -> Scene | None: ...


@dataclass(frozen=True)
class Request:
    """The frame one side's pipeline is asked for."""

    settings: Settings
    """What the pipeline runs: the side's settings with the display fields pinned
    (explorer.ui.controller.PINNED_DISPLAY) and, while interacting, a reduced size."""
    keep_steps: bool = False
    need_audit: str = "off"
    """The audit mode (explorer.lpv.audit.AUDIT_MODES) what is shown needs."""
    interactive: bool = False
    """Made while the camera is dragged (reduced size)."""

    def covered_by(self, done: Request | None) -> bool:
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
    finished: bool = False
    """A side's job finished this frame: its frame is drawn with what a new result costs
    the panels and the drawing (``frame_budget.ResultDrawing``)."""
    snapshot_ms: float = 0.0
    """Milliseconds of the finished frames' snapshots this frame (part of ``work_ms``)."""
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
    job: Job | None = None
    request: Request | None = None
    """The request of the job in flight."""
    done: Request | None = None
    """The request of the last finished frame (what :attr:`result` shows)."""
    refines: tuple[Request, bool] | None = None
    """(the request in flight, whether it only resizes ``done``'s frame): remembered so
    that the previews' pacing compares the settings once per request."""
    failed: Request | None = None
    result: FrameResult | None = None
    progress: Progress | None = None
    previewed: int = 0
    """Propagation steps of the job's last preview."""
    previews: int = 0
    """Previews of the job in flight so far (its first is coarse: ``FIRST_PREVIEW_SCALE``)."""
    previewed_at: float = 0.0
    propagate_from: tuple[float, int] | None = None
    """(:attr:`job_ms`, steps) at the job's first preview: the propagation's pace since."""
    preview_ms: float = 0.0
    """What the side's last preview cost (gather, copy; display at the full size)."""
    previews_ms: float = 0.0
    """What the job's previews cost so far (in :attr:`job_ms`)."""
    first_preview_ms: float = 0.0
    """What the side's last first preview of a job cost (the coarse one): a job's first
    preview is taken in the frame whose unit made it possible only when this much of the
    frame budget is left (explorer/ui/controller.py ``_advance``)."""
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



def keeps_steps(state: AppState, side: str) -> bool:
    """Whether ``side``'s frame keeps grid_0..grid_N of every cascade: the in-scene
    overlays show the light in flight (drawn over both sides of a split view; a lesson's
    ``[steps.show]`` sets them), or the Inspect panel steps through A's propagation."""
    return state.overlays.needs_steps or (side == "A"
                                          and state.inspect.source == "propagation")



class StageCounter:
    """A job's progress callback that counts each stage once when it starts."""

    def __init__(self, counts: Counter) -> None:
        self.counts = counts
        self.last: str | None = None

    def __call__(self, stage: str, done: int, total: int) -> None:
        if stage != self.last:
            self.last = stage
            self.counts.update([stage])

