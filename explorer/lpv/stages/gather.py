"""The ``gather`` stage: linear direct and LPV indirect radiance per pixel
(explorer/lpv/passes/gather.py) in bands of rows (one per unit), then the read-back of the
targets (copied in one unit, taken once the copies are done, a unit a target:
explorer/lpv/work_units.py ``read_back_later``) and their sums and checks (one more).
:meth:`Stage.gather_levels` also gathers a job's accumulation as it is (the progressive
previews)."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

from explorer.gl.gpu_sync import DeferredRead
from explorer.lpv import guards
from explorer.lpv.corrections import uniforms_read_by
from explorer.lpv.passes.gather import (
    TARGETS,
    GatherImages,
    GatherInputs,
    GatherPass,
    Glossy,
    bands,
)
from explorer.lpv.stage_list import StageDecl
from explorer.lpv.stages.base import Stage as StageBase
from explorer.lpv.stages.base import StageHost
from explorer.lpv.work_units import read_back_later, read_back_units

if TYPE_CHECKING:
    from explorer.lpv.cascades import SampledGrid
    from explorer.lpv.job import Job

@dataclass(frozen=True)
class Params:
    """What the gather reads of the Settings (and the eye the glossy term reflects)."""

    inputs: GatherInputs

    @classmethod
    def of(cls, settings, eye) -> Params:
        """The Settings' gather, its glossy term (when on) seen from ``eye``."""
        glossy = Glossy(float(settings.glossy_roughness), float(settings.glossy_strength),
                        int(settings.glossy_samples), tuple(map(float, eye))
                        ) if settings.glossy else None
        switches = settings.corrections.as_uniforms()
        return cls(GatherInputs(bool(settings.gather_damping),
                                bool(settings.gather_net_flux), int(settings.shadow_kernel),
                                glossy, tuple((name, switches[name])
                                              for name in uniforms_read_by("gather"))))


class Stage(StageBase):
    def __init__(self, host: StageHost, decl: StageDecl) -> None:
        super().__init__(host, decl)
        self.gather = GatherPass(host.ctx, host.programs)
        self.state.gather_pass = self.gather
        self.reads = [DeferredRead(host.ctx) for _ in TARGETS]

    def units(self, job: Job) -> int:
        return len(bands((job.settings.width, job.settings.height))) + read_back_units(
            len(TARGETS), apart=True) + 1

    def work(self, job: Job) -> Iterator[None]:
        s, host = job.settings, self.host
        host.timer.reset("gather")
        for band in bands((s.width, s.height)):
            host.timer.timed("gather", lambda: self.gather_levels(s, band), accumulate=True)
            yield
        targets = self.gather.targets
        arrays = yield from read_back_later(self.reads, [targets[name] for name in TARGETS],
                                            apart=True)
        yield       # the sums and the checks of the arrays: a unit of their own
        self.state.gather = GatherImages(**dict(zip(TARGETS, arrays)))
        self.state.warnings["gather"] = guards.arrays_warnings_later("gather", arrays, s)

    def gather_levels(self, s, rows: tuple[int, int] | None = None,
                      into: GatherPass | None = None,
                      size: tuple[int, int] | None = None,
                      grid: SampledGrid | None = None) -> None:
        """The gather of every level's accumulation as it is now (docs/MODEL.md "Final
        gather", "Cascades"), of the rows ``rows`` or the whole image; ``into``/``size``:
        another gather pass's targets, at that size (a reduced preview); ``grid``: these
        grids instead of the accumulation (a preview of the injected light)."""
        host, state = self.host, self.state
        (into or self.gather).run(
            state.gbuffer_pass, host.light_views.shadow_maps,
            state.sampled_grid() if grid is None else grid,
            Params.of(s, host.scene_state.scene.camera.eye).inputs, rows=rows, size=size)

    def release(self) -> None:
        self.gather.release()
        for read in self.reads:
            read.release()
