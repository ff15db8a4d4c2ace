"""The ``fog`` stage: the medium's march in bands of rows (one per unit), then the
read-back of its two targets (explorer/lpv/fog.py, docs/MODEL.md "Fog"); nothing while
``fog`` is off."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from explorer.lpv import guards
from explorer.lpv.fog import TARGETS, FogPass, Medium
from explorer.lpv.frame_stages.base import Stage as StageBase
from explorer.lpv.frame_stages.base import StageHost
from explorer.lpv.frame_state import FogImages
from explorer.lpv.gather import bands
from explorer.lpv.stage_list import StageDecl
from explorer.gl.gpu_sync import DeferredRead
from explorer.lpv.work_units import read_back_later

if TYPE_CHECKING:
    from explorer.lpv.job import Job

Params = Medium
"""What the fog reads of the Settings (``Medium.of(settings)``)."""


class Stage(StageBase):
    def __init__(self, host: StageHost, decl: StageDecl) -> None:
        super().__init__(host, decl)
        self.fog = FogPass(host.ctx, host.programs)
        self.state.fog_pass = self.fog
        self.reads = [DeferredRead(host.ctx) for _ in TARGETS]

    def units(self, job: Job) -> int:
        s = job.settings
        return len(bands((s.width, s.height))) + 2 if s.fog else 1

    def work(self, job: Job) -> Iterator[None]:
        s, host, state = job.settings, self.host, self.state
        if not s.fog:
            host.timer.forget("fog")
            state.fog = None
            state.warnings["fog"] = []
            return
        grid = state.sampled_grid()
        medium, shadow = Params.of(s), host.light_views.shadow_maps
        host.timer.reset("fog")
        for band in bands((s.width, s.height)):
            host.timer.timed("fog", lambda: self.fog.run(
                state.gbuffer_pass, shadow, host.scene_state.scene, grid, medium,
                shader_filter=state.gather_pass.shader_filter, rows=band), accumulate=True)
            yield
        direct, lpv = yield from read_back_later(
            self.reads, [self.fog.targets[name] for name in TARGETS])
        state.fog = FogImages(direct[..., 3].copy(), direct[..., :3], lpv[..., :3])
        state.warnings["fog"] = guards.arrays_warnings("fog", [direct, lpv], s)

    def release(self) -> None:
        self.fog.release()
        for read in self.reads:
            read.release()
