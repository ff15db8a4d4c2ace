"""The ``grid`` stage (by value): the GridSpec of each cascade, the grid enclosing the
scene or the cascades around the camera's focus point (explorer/lpv/cascades.py)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from explorer.lpv.cascades import frame_specs
from explorer.lpv.stages.base import Stage as StageBase

if TYPE_CHECKING:
    from explorer.lpv.job import Job


class Stage(StageBase):
    def evaluate(self, job: Job) -> tuple:
        """The tuple of cascade specs (what the stages downstream see)."""
        s = job.settings
        self.state.specs = frame_specs(s, self.host.scene_state.for_settings(s))
        return tuple(self.state.specs)
