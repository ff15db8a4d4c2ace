"""The ``scene`` stage: load the mesh (once per scene name) and pose its objects
(:meth:`explorer.lpv.scene_state.SceneState.load_and_pose`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from explorer.lpv import guards
from explorer.lpv.stages.base import Stage as StageBase

if TYPE_CHECKING:
    from explorer.lpv.job import Job


class Stage(StageBase):
    def run(self, job: Job) -> None:
        base = self.host.scene_state.load_and_pose(job.settings,
                                                    wait=not self.host.timer.queued)
        self.state.warnings["scene"] = guards.found(
            guards.scale_warning(base.bounds_min, base.bounds_max))
