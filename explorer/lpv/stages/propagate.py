"""The ``propagate`` stage: ``iterations`` steps in every cascade (explorer/lpv/passes/propagate.py)
with the energy audit the job asks for, time-sliced in slabs of a step."""

from __future__ import annotations

import time
from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

import explorer.lpv.passes.propagate as propagate_pass
from explorer.gl.gpu_sync import DeferredRead, GpuWait
from explorer.lpv import guards
from explorer.lpv.audit import audit_covers
from explorer.lpv.cascades import cascade_iterations, level_pass_name
from explorer.lpv.corrections import Corrections
from explorer.lpv.limits import audit_fits, audit_skipped_warning
from explorer.lpv.stage_list import StageDecl
from explorer.lpv.stages.base import Stage as StageBase
from explorer.lpv.stages.base import StageHost

if TYPE_CHECKING:
    from explorer.lpv.job import Job

GROUP_MS = 2.0
"""A unit of the propagation dispatches slabs until it has spent this many milliseconds:
the small grids' steps (or a GPU's, whose dispatches only queue work) are grouped, so
that their per-unit Python (the job's bookkeeping, a timer query, the bindings a step
shares with the next) is paid once for several steps; a slab that takes longer is a unit
of its own, as before."""


def advance_group(levels: list, limit_ms: float = GROUP_MS) -> None:
    """Slabs of the level that is least far along, then of the next least far along...,
    in the order one slab per unit would run them, until ``limit_ms`` is spent (at least
    one slab) or every level is finished; slabs of one level in a row keep its
    bindings."""
    start = time.perf_counter()
    if len(levels) == 1:            # one level: its slabs in a row, all keeping its bindings
        levels[0].running.advance_for(limit_ms, start)
        return
    last = None
    while True:
        running = [level.running for level in levels if not level.running.finished]
        if not running:
            return
        behind = min(running, key=lambda run: run.fraction)
        behind.advance(bound=behind is last)
        last = behind
        if (time.perf_counter() - start) * 1e3 >= limit_ms:
            return


@dataclass(frozen=True)
class Params:
    """What the propagation reads of the Settings."""

    corrections: Corrections
    steps: tuple[int, ...]
    """Each cascade's iterations (``cascade_iterations``), finest first."""
    bounces: int
    neighbours: int
    visibility: str = "linear"
    flux_budget: bool = False
    reprojection: str = "face-normal"

    @classmethod
    def of(cls, settings, cascades: int) -> Params:
        return cls(settings.corrections,
                   tuple(cascade_iterations(settings, k) for k in range(cascades)),
                   int(settings.bounces), int(settings.neighbours),
                   settings.geometry_visibility, bool(settings.flux_budget),
                   settings.reprojection)


class Stage(StageBase):
    def __init__(self, host: StageHost, decl: StageDecl) -> None:
        super().__init__(host, decl)
        self.reads: list[list[DeferredRead]] = []
        """Per level: the audit's sums and the accumulation's three colour channels."""

    def level_reads(self, level: int) -> list[DeferredRead]:
        while len(self.reads) <= level:
            self.reads.append([DeferredRead(self.host.ctx) for _ in range(4)])
        return self.reads[level]

    def units(self, job: Job) -> int:
        """The steps of every level together (each step is one or more slabs)."""
        return max(1, sum(Params.of(job.settings, len(self.state.specs)).steps))

    def audit_mode(self, job: Job, cells: tuple[int, int, int]) -> str:
        """The audit mode a level of ``cells`` propagates with for ``job``: the one it
        asks for, but ``flux`` for ``full`` when the per-cell records do not fit this
        driver's storage blocks (:func:`audit_fits`; the flux needs no records)."""
        if job.need_audit == "full" and not audit_fits(cells, self.host.limits):
            return "flux"
        return job.need_audit

    def satisfied(self, job: Job) -> bool:
        """Whether the last propagation kept the steps and the audit ``job`` asks for."""
        for k, level in enumerate(self.state.cascades):
            output = level.output
            if output is None:
                return False
            if self.keeps_steps(job, k) and output.steps is None:
                return False
            if not audit_covers(output.audit.mode,
                                self.audit_mode(job, level.injected.cells)):
                return False
        return True

    def keeps_steps(self, job: Job, level: int) -> bool:
        """Whether cascade ``level`` records its steps for ``job`` (the host's
        ``steps_levels`` finest levels, when the job asks for steps)."""
        limit = self.host.steps_levels
        return job.keep_steps and (limit is None or level < limit)

    def work(self, job: Job) -> Iterator[int]:
        """Every level's propagation: a unit to start each level and one for each channel
        of grid_0 copied into its accumulation, the slabs of the steps (``slabs``) grouped
        into units of about :data:`GROUP_MS` (:func:`advance_group`), the levels
        interleaved so that each is as far along as the others (a progressive picture
        shows all cascades growing together), and two to finish each level (its audit's
        sums and its accumulation copied for reading back, then taken once the copies are
        done: explorer/lpv/job.py ``GpuWait``). Yields the steps done, all levels together."""
        host, state = self.host, self.state
        levels, specs = state.cascades, state.specs
        p = Params.of(job.settings, len(levels))
        timed = host.timer.timed
        host.timer.reset("propagate")
        audit = [self.audit_mode(job, spec.cells) for spec in specs]
        # every unit but the last level's read-back is followed by another
        try:
            for k, (level, spec) in enumerate(zip(levels, specs)):
                level.output = None
                level.running = timed("propagate", lambda: level.propagate.start(
                    level.injected, spec, p.corrections, p.steps[k], level.volume,
                    keep_steps=self.keeps_steps(job, k), bounces=p.bounces, audit=audit[k],
                    neighbours=p.neighbours, visibility=p.visibility,
                    flux_budget=p.flux_budget, reprojection=p.reprojection),
                    accumulate=True)
                yield 0
                running = level.running
                while running.copies_left:      # grid_0 into the accumulation, a channel a unit
                    timed("propagate", running.copy_next, accumulate=True)
                    yield 0
            while not all(level.running.finished for level in levels):
                # within a frame budget no further than the budget left allows
                left = job.unit_budget_ms
                limit = GROUP_MS if left is None else min(GROUP_MS, left)
                timed("propagate", lambda: advance_group(levels, limit), accumulate=True)
                yield sum(level.running.done for level in levels)
            warnings = []
            for k, level in enumerate(levels):
                reads = self.level_reads(k)
                running = level.running
                timed("propagate", lambda: (running.finish_later(reads[0]),
                                            running.accumulated.read_later(reads[1:])),
                      accumulate=True)
                yield GpuWait(reads, sum(p.steps))     # the read-back follows
                level.output = running.output(reads[0])
                level.accumulated = running.accumulated.taken(reads[1:])
                warnings.append(guards.found(guards.flux_warning(
                    level_pass_name("inject", k, len(levels)), level.output.audit.injected,
                    p.corrections)))
                warnings.append(guards.arrays_warnings_later(
                    level_pass_name("propagate", k, len(levels)), [level.accumulated],
                    job.settings))
                if audit[k] != job.need_audit:
                    warnings.append([audit_skipped_warning(specs[k].cells, host.limits)])
                if k < len(levels) - 1:
                    yield sum(p.steps)
            state.warnings["propagate"] = guards.joined(warnings)
        finally:
            for level in levels:
                level.running = None

    def release_between_runs(self) -> int:
        """Release the levels' read-backs of their accumulation (taken into the levels'
        arrays at the run's end) of ``SPARE_GRID_BYTES`` or more (a 64³ L1 grid's are
        12 MiB a level); the audit's stays (its sums are read when first asked for)."""
        released = 0
        for reads in self.reads:
            # a level's three channels together, as the grid they copy (4 MiB each at 64³)
            taken = sum(read.nbytes for read in reads[1:])
            if taken and taken >= propagate_pass.SPARE_GRID_BYTES:
                released += taken
                for read in reads[1:]:
                    read.release()
        return released

    def release(self) -> None:
        for reads in self.reads:
            for read in reads:
                read.release()
        self.reads = []
