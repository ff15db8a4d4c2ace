"""The ``rsm`` stage: one RSM per view of every light that shines (a unit each), then the
atlas of their shadow maps and VPLs (several views) and the read-back (one unit); the
light views' passes are :class:`explorer.lpv.light_views.LightViews`'."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from explorer.lpv import guards
from explorer.lpv.light_views import LightViews
from explorer.lpv.limits import check_memory
from explorer.lpv.stages.base import Stage as StageBase

if TYPE_CHECKING:
    from explorer.lpv.job import Job


class Stage(StageBase):
    def units(self, job: Job) -> int:
        scene = self.host.scene_state.for_settings(job.settings)
        return len(LightViews.of(scene, job.settings.rsm_size)) + 1

    def work(self, job: Job) -> Iterator[None]:
        s, host = job.settings, self.host
        views = LightViews.of(host.scene_state.for_settings(s), s.rsm_size)
        check_memory(s, host.memory_budget_bytes, views=len(views))
        yield from host.light_views.render(views, host.scene_state.buffers,
                                           host.limits.max_framebuffer_size)
        self.state.rsm, checked = host.light_views.rsm_read_back()
        self.state.warnings["rsm"] = guards.arrays_warnings("rsm", checked, s)
