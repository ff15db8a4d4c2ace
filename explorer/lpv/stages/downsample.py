"""The ``downsample`` stage: the VPLs the injection reads (the RSM texels, merged blocks
of them, or hand-made VPLs: :meth:`explorer.lpv.light_views.LightViews.choose_vpls_later`) and
their read-back (copied in the stage's first unit, taken in the second once the copies
are done; a large set's arrays a unit each: explorer/lpv/vpl.py ``TAKEN_APART_TEXELS``)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from explorer.gl.gpu_sync import DeferredRead, GpuWait
from explorer.lpv import guards
from explorer.lpv.stage_list import StageDecl
from explorer.lpv.stages.base import Stage as StageBase
from explorer.lpv.stages.base import StageHost

if TYPE_CHECKING:
    from explorer.lpv.job import Job


class Stage(StageBase):
    def __init__(self, host: StageHost, decl: StageDecl) -> None:
        super().__init__(host, decl)
        self.reads: list[list[DeferredRead]] = []
        """Per VPL set, the copies of its four textures (reused)."""

    def extra_input(self, job: Job) -> object:
        return job.vpls_key            # hand-made VPLs are an input of their own

    def units(self, job: Job) -> int:
        return 2

    def work(self, job: Job) -> Iterator[GpuWait | int]:
        s, host = job.settings, self.host
        views = host.light_views
        views.choose_vpls_later(s, job.vpls, self.state.specs[0],
                                host.limits.max_framebuffer_size)
        reads = views.reads_for(self.reads)
        for vpl_set, set_reads in zip(views.vpl_sets, reads):
            vpl_set.read_later(set_reads)
        yield GpuWait([read for vpl_set, set_reads in zip(views.vpl_sets, reads)
                       for read in set_reads[:len(vpl_set.all_textures)]])
        taking = views.vpls_taken_units(reads, job.vpls is not None)
        while True:         # a large set's arrays a unit each (the progress stays at 1)
            try:
                next(taking)
            except StopIteration as taken:
                self.state.vpls = taken.value
                break
            yield 1
        # hand-made VPLs are the caller's: a NaN in them shows up at the injection
        self.state.warnings["downsample"] = [] if job.vpls is not None else \
            guards.arrays_warnings_later("downsample", [self.state.vpls.vpls.flux], s)

    def release(self) -> None:
        for set_reads in self.reads:
            for read in set_reads:
                read.release()
        self.reads = []
