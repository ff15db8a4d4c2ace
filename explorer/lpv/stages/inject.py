"""The ``inject`` stage: the VPLs into the SH light grid of every cascade
(explorer/lpv/passes/inject.py): per cascade one unit, or the point path's draws in batches
of VPLs (a large RSM's) and a large grid's copy of each channel (``InjectPass.unit_count``)."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

import explorer.lpv.passes.propagate as propagate_pass
from explorer.lpv.audit import check_finite
from explorer.lpv.cascades import level_pass_name
from explorer.lpv.corrections import Corrections
from explorer.lpv.passes.inject import InjectPass, vpl_count
from explorer.lpv.stage_list import StageDecl
from explorer.lpv.stages.base import Stage as StageBase
from explorer.lpv.stages.base import StageHost

if TYPE_CHECKING:
    from explorer.lpv.job import Job


@dataclass(frozen=True)
class Params:
    """What the injection reads of the Settings."""

    corrections: Corrections
    mode: str
    """``injection_mode``: points (rasterised) or compute."""
    offset_cells: float
    grid_format: str
    sh_order: int

    @classmethod
    def of(cls, settings) -> Params:
        return cls(settings.corrections, settings.injection_mode,
                   float(settings.injection_offset_cells), settings.grid_format,
                   int(settings.sh_order))


class Stage(StageBase):
    def __init__(self, host: StageHost, decl: StageDecl) -> None:
        super().__init__(host, decl)
        self.inject = InjectPass(host.ctx, host.programs)

    def units(self, job: Job) -> int:
        mode, order = job.settings.injection_mode, int(job.settings.sh_order)
        vpls = vpl_count(self.host.light_views.vpl_textures)
        return sum(InjectPass.unit_count(mode, spec.cells, order, vpls)
                   for spec in self.state.specs)

    def work(self, job: Job) -> Iterator[None]:
        p, host, specs = Params.of(job.settings), self.host, self.state.specs
        levels = self.levels()
        host.timer.reset("inject")
        for k, (level, spec) in enumerate(zip(levels, specs)):
            grid = level.grid(spec.cells, p.grid_format, p.sh_order)
            units = self.inject.run_units(host.light_views.vpl_textures, spec, p.corrections,
                                          p.mode, grid, p.offset_cells)
            while host.timer.timed("inject", lambda: next(units, False), accumulate=True) \
                    is None:
                yield                        # the level's next unit follows
            if job.settings.debug_nan:       # a check, not an input: no key holds it
                check_finite(grid.read(), level_pass_name("inject", k, len(levels)))
            if k < len(levels) - 1:
                yield

    def release_between_runs(self) -> int:
        """The point draws' layers of a large grid (12 MiB at 64³ L1): only an injection
        in progress uses them."""
        return self.inject.release_between_runs(propagate_pass.SPARE_GRID_BYTES)

    def release(self) -> None:
        self.inject.release()
