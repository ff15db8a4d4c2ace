"""The ``display`` stage: exposure, auto exposure, tone curve and encoding of the shown
RGBA8 image, the fog composed over the surfaces (explorer/lpv/passes/display.py, docs/MODEL.md
"Display"); ``Pipeline.display_scale_override`` is an input of its own."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

from explorer.lpv.passes.display import AutoExposure, DisplayPass
from explorer.lpv.passes.fog import TARGETS as FOG_TARGETS
from explorer.lpv.stage_list import StageDecl
from explorer.lpv.stages.base import Stage as StageBase
from explorer.lpv.stages.base import StageHost

if TYPE_CHECKING:
    from explorer.lpv.job import Job


@dataclass(frozen=True)
class Params:
    """What the display reads of the Settings."""

    exposure: float
    indirect_only: bool
    tone_map: str
    auto_exposure: bool
    fog: bool
    """Compose the fog (the ``fog`` stage's targets) over the surfaces."""

    @classmethod
    def of(cls, settings) -> Params:
        return cls(float(settings.exposure), bool(settings.indirect_only), settings.tone_map,
                   bool(settings.auto_exposure), bool(settings.fog))


class Stage(StageBase):
    def __init__(self, host: StageHost, decl: StageDecl) -> None:
        super().__init__(host, decl)
        self.display = DisplayPass(host.ctx, host.programs)
        self.auto_exposure = AutoExposure()

    def extra_input(self, job: Job) -> object:
        return self.host.display_scale_override

    def units(self, job: Job) -> int:
        return 3

    def work(self, job: Job) -> Iterator[None]:
        """Three units: the display scale in two (the auto exposure meters the read-back
        image on the CPU, then averages it: ``AutoExposure.measure``; the second does
        nothing when there is nothing to measure), then the display pass."""
        p = Params.of(job.settings)
        measuring = self.frame_scale(p)
        given = [next(measuring)]
        yield
        given.extend(measuring)
        scale = given[-1]
        assert scale is not None, "frame_scale ends with the scale"
        self.state.display_scale = scale
        yield
        self.show(p, self.state.display_scale)

    def show(self, p: Params, scale: float, fog: bool = True) -> None:
        """The display pass on the gather's targets as they are now (and the fog's, when
        the frame has one and ``fog``)."""
        state = self.state
        targets = state.gather_pass.targets
        fog_targets = None
        if fog and p.fog and state.fog is not None:
            fog_targets = tuple(state.fog_pass.targets[name] for name in FOG_TARGETS)
        self.host.timer.timed("display", lambda: self.display.run(
            targets["direct"], targets["indirect"], p.exposure, p.indirect_only, p.tone_map,
            scale, fog_targets))

    def frame_scale(self, p: Params) -> Iterator[float | None]:
        """The display scale of the frame just gathered: the override, or the auto
        exposure of its unexposed image over the pixels that show a surface (measured
        once per gathered frame and ``indirect_only``; an exposure change reuses it), in
        the units of ``AutoExposure.measure``: None after each but the last, which gives
        the scale."""
        override = self.host.display_scale_override
        if override is not None:
            yield float(override)
        elif not p.auto_exposure:
            yield 1.0
        else:
            state = self.state
            yield (yield from self.auto_exposure.measure(
                state.gather, state.fog if p.fog else None, p.indirect_only,
                state.gbuffer.position))

    def release(self) -> None:
        self.display.release()
