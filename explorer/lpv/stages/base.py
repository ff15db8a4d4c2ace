"""What every stage object is (:class:`Stage`) and what it may use of the pipeline that
runs it (:class:`StageHost`)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING, Protocol

import moderngl

from explorer.gl.program import ProgramCache
from explorer.lpv.cascade_level import CascadeLevel
from explorer.lpv.frame_state import FrameState
from explorer.lpv.light_views import LightViews
from explorer.lpv.limits import DriverLimits
from explorer.lpv.scene_state import SceneState
from explorer.lpv.stage_list import StageDecl
from explorer.lpv.timing import PassTimer
from explorer.lpv.work_units import single_unit

if TYPE_CHECKING:
    from explorer.lpv.job import Job


class StageHost(Protocol):
    """The services a stage uses (:class:`explorer.lpv.pipeline.Pipeline` provides them):
    the GL context and its programs, the timer, the driver's limits and the memory
    budget, the two sides every stage reads (the scene and the light views) and the
    frame state the stages hand on to each other."""

    ctx: moderngl.Context
    programs: ProgramCache
    timer: PassTimer
    limits: DriverLimits
    memory_budget_bytes: int
    light_views: LightViews
    scene_state: SceneState
    state: FrameState
    display_scale_override: float | None
    steps_levels: int | None
    """How many cascade levels, finest first, keep their propagation steps for a job that
    asks for them (None: every level)."""


class Stage:
    """One stage of the frame (:data:`explorer.lpv.stage_list.STAGE_LIST` declares its
    facts, :attr:`decl`). A subclass does its work in :meth:`run` (one unit) or
    overrides :meth:`work` (a generator that yields after every unit but its last, and
    may yield its progress in its own count) and :meth:`units`; it reads its upstream
    stages' fields of :attr:`state` and writes its own."""

    def __init__(self, host: StageHost, decl: StageDecl) -> None:
        self.host = host
        self.decl = decl
        self.name = decl.name

    @property
    def state(self) -> FrameState:
        return self.host.state

    def levels(self) -> list[CascadeLevel]:
        """The frame's cascade levels, one per spec of the ``grid`` stage (made or
        released here: the stages that fill them run in either order)."""
        host = self.host
        return self.state.levels_for_specs(lambda: CascadeLevel(host.ctx, host.programs))

    def units(self, job: Job) -> int:
        """The total of the stage's progress count for ``job``."""
        return 1

    def work(self, job: Job) -> Iterator[int | None]:
        """The stage's work as a generator of units (default: :meth:`run` as one)."""
        return single_unit(lambda: self.run(job))

    def run(self, job: Job) -> None:
        raise NotImplementedError(f"stage {self.name} defines neither run nor work")

    def extra_input(self, job: Job) -> object:
        """What the stage's key holds besides Settings fields and upstream keys."""
        return None

    def satisfied(self, job: Job) -> bool:
        """Whether the last completed run has everything ``job`` asks for."""
        return True

    def evaluate(self, job: Job) -> object:
        """The value of a by-value stage (``StageDecl.by_value``)."""
        raise ValueError(f"{self.name} is not a by-value stage")

    def release_between_runs(self) -> int:
        """Release what only a run of the stage in progress uses (called with no job in
        progress); the bytes released."""
        return 0

    def release(self) -> None:
        """Release the stage's GPU resources."""
