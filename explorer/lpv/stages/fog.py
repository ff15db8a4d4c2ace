"""The ``fog`` stage: the medium's march in bands of rows (one per unit), then the
read-back of its two targets (explorer/lpv/passes/fog.py, docs/MODEL.md "Fog"); nothing while
``fog`` is off."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

from explorer.gl.gpu_sync import DeferredRead
from explorer.lpv import guards
from explorer.lpv.passes.fog import TARGETS, FogImages, FogPass, Medium
from explorer.lpv.passes.gather import bands
from explorer.lpv.stage_list import StageDecl
from explorer.lpv.stages.base import Stage as StageBase
from explorer.lpv.stages.base import StageHost
from explorer.lpv.work_units import read_back_later

if TYPE_CHECKING:
    from explorer.lpv.job import Job

@dataclass(frozen=True)
class Params:
    """What the fog reads of the Settings."""

    medium: Medium

    @classmethod
    def of(cls, settings) -> Params:
        """The medium the Settings describe (``fog_g`` is used only with the HG phase)."""
        g = settings.fog_g if settings.fog_phase == "henyey-greenstein" else 0.0
        return cls(Medium(float(settings.fog_density), float(settings.fog_albedo), float(g),
                          int(settings.fog_steps)))


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
        medium, shadow = Params.of(s).medium, host.light_views.shadow_maps
        host.timer.reset("fog")
        for band in bands((s.width, s.height)):
            host.timer.timed("fog", lambda: self.fog.run(
                state.gbuffer_pass, shadow, host.scene_state.scene, grid, medium,
                shader_filter=state.gather_pass.shader_filter, rows=band), accumulate=True)
            yield
        direct, lpv = yield from read_back_later(
            self.reads, [self.fog.targets[name] for name in TARGETS])
        state.fog = FogImages(direct[..., 3].copy(), direct[..., :3], lpv[..., :3])
        state.warnings["fog"] = guards.arrays_warnings_later("fog", [direct, lpv], s)

    def release(self) -> None:
        self.fog.release()
        for read in self.reads:
            read.release()
