"""The ``grid`` stage (by value): the GridSpec of each cascade, the grid enclosing the
scene or the cascades around the camera's focus point (explorer/lpv/cascades.py)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from explorer.lpv.cascades import frame_specs
from explorer.lpv.stages.base import Stage as StageBase

if TYPE_CHECKING:
    from explorer.lpv.job import Job


class Stage(StageBase):
    _kept: tuple | None = None
    """(settings, scene, specs) of the last evaluation: both are frozen, so the same
    objects give the same specs (a frame asks every time, most often for the same)."""

    def evaluate(self, job: Job) -> tuple:
        """The tuple of cascade specs (what the stages downstream see)."""
        s = job.settings
        scene = self.host.scene_state.for_settings(s)
        kept = self._kept
        if kept is None or kept[0] is not s or kept[1] is not scene:
            kept = self._kept = (s, scene, tuple(frame_specs(s, scene)))
        self.state.specs = list(kept[2])
        return kept[2]
