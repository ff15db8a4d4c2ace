"""The ``downsample`` stage: the VPLs the injection reads (the RSM texels, merged blocks
of them, or hand-made VPLs: :meth:`explorer.lpv.light_views.LightViews.choose_vpls`) and
their read-back."""

from __future__ import annotations

from typing import TYPE_CHECKING

from explorer.lpv import guards
from explorer.lpv.stages.base import Stage as StageBase

if TYPE_CHECKING:
    from explorer.lpv.job import Job


class Stage(StageBase):
    def extra_input(self, job: Job) -> object:
        return job.vpls_key            # hand-made VPLs are an input of their own

    def run(self, job: Job) -> None:
        s, host = job.settings, self.host
        self.state.vpls = host.light_views.choose_vpls(
            s, job.vpls, self.state.specs[0], host.limits.max_framebuffer_size)
        # hand-made VPLs are the caller's: a NaN in them shows up at the injection
        self.state.warnings["downsample"] = [] if job.vpls is not None else \
            guards.arrays_warnings("downsample", [self.state.vpls.vpls.flux], s)
