"""The ``rsm`` stage: one RSM per view of every light that shines (a unit each), then the
atlas of their shadow maps and VPLs (several views) with the read-back's copies (one
unit), and the read-back taken (one more, once the copies are done); the
light views' passes are :class:`explorer.lpv.light_views.LightViews`'."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from explorer.gl.gpu_sync import DeferredRead
from explorer.lpv import guards
from explorer.lpv.light_views import LightViews
from explorer.lpv.limits import check_memory
from explorer.lpv.passes.rsm import view_count
from explorer.lpv.stage_list import StageDecl
from explorer.lpv.stages.base import Stage as StageBase
from explorer.lpv.stages.base import StageHost
from explorer.lpv.work_units import read_back_later

if TYPE_CHECKING:
    from explorer.lpv.job import Job


class Stage(StageBase):
    def __init__(self, host: StageHost, decl: StageDecl) -> None:
        super().__init__(host, decl)
        self.reads: list[DeferredRead] = []
        """The read-back's copies (grown to the views' count, reused)."""
        self._views: tuple | None = None
        """(scene, RSM size, snap, scene as loaded, their views) of the last run: the scenes
        are frozen, so the same objects give the same views (kept, not made anew)."""

    def views(self, s) -> list:
        """The RSM views of ``s``'s scene (``LightViews.of``), the last run's while the
        scene objects and the RSM's size and snap are the same."""
        state = self.host.scene_state
        scene, placed = state.for_settings(s), state.base(s.scene)
        kept = self._views
        if kept is None or kept[0] is not scene or kept[3] is not placed or \
                kept[1] != s.rsm_size or kept[2] != s.rsm_snap:
            kept = self._views = (scene, s.rsm_size, s.rsm_snap, placed,
                                  LightViews.of(scene, s.rsm_size, s.rsm_snap, placed))
        return kept[4]

    def release(self) -> None:
        for read in self.reads:
            read.release()
        self.reads = []

    def units(self, job: Job) -> int:
        return view_count(self.host.scene_state.for_settings(job.settings)) + 2

    def satisfied(self, job: Job) -> bool:
        """A frame that keeps its steps needs every view's RSM read back (one view always
        is)."""
        rsm = self.state.rsm
        return not job.keep_steps or (rsm is not None and rsm.views is not None)

    def work(self, job: Job) -> Iterator[None]:
        s, host = job.settings, self.host
        views = self.views(s)
        check_memory(s, host.memory_budget_bytes, views=len(views))
        yield from host.light_views.render(views, host.scene_state.buffers,
                                           host.limits.max_framebuffer_size)
        # the read-back is copied now and taken in the next unit (work_units.py)
        every_view = job.keep_steps       # a dump writes every view's RSM
        textures = host.light_views.rsm_textures_read(every_view)
        while len(self.reads) < len(textures):
            self.reads.append(DeferredRead(host.ctx))
        for read in self.reads[len(textures):]:     # views gone (a point light's six)
            read.release()
        del self.reads[len(textures):]
        arrays = yield from read_back_later(self.reads, textures)
        self.state.rsm, checked = host.light_views.rsm_read_back(arrays, every_view)
        # checked when read while the frame keeps every array it checks (one view, or all
        # kept), else now: a kept frame must not hold the other views' arrays for it
        self.state.warnings["rsm"] = guards.arrays_warnings_later("rsm", checked, s) \
            if self.state.rsm.views is not None else guards.arrays_warnings("rsm", checked, s)
