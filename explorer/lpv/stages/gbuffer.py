"""The ``gbuffer`` stage: the camera's position, normal and albedo
(explorer/lpv/passes/gbuffer.py), then the read-back of its textures (copied in one unit, taken
a texture a unit once the copies are done: explorer/lpv/work_units.py ``read_back_later``)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from explorer.gl.gpu_sync import DeferredRead
from explorer.lpv import guards
from explorer.lpv.frame_state import GBufferImages
from explorer.lpv.passes.gbuffer import TARGETS, GBufferPass
from explorer.lpv.stage_list import StageDecl
from explorer.lpv.stages.base import Stage as StageBase
from explorer.lpv.stages.base import StageHost
from explorer.lpv.work_units import read_back_later, read_back_units

if TYPE_CHECKING:
    from explorer.lpv.job import Job


class Stage(StageBase):
    def __init__(self, host: StageHost, decl: StageDecl) -> None:
        super().__init__(host, decl)
        self.gbuffer = GBufferPass(host.ctx, host.programs)
        self.state.gbuffer_pass = self.gbuffer
        self.reads = [DeferredRead(host.ctx) for _ in TARGETS]

    def units(self, job: Job) -> int:
        return 1 + read_back_units(len(TARGETS), apart=True)

    def work(self, job: Job) -> Iterator[None]:
        s, host = job.settings, self.host
        scene = host.scene_state.for_settings(s)
        host.timer.timed("gbuffer", lambda: self.gbuffer.run(
            host.scene_state.buffers, scene, (s.width, s.height)))
        yield
        arrays = yield from read_back_later(self.reads, self.gbuffer.textures, apart=True)
        self.state.gbuffer = GBufferImages(*arrays)
        self.state.warnings["gbuffer"] = guards.arrays_warnings_later("gbuffer", arrays, s)

    def release(self) -> None:
        self.gbuffer.release()
        for read in self.reads:
            read.release()
