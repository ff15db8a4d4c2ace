"""The render size follows the View panel's pixels (times ``AppState.render_scale``):
at once before the first picture, otherwise once resizing pauses for
:data:`RESIZE_SETTLE_S`, so that dragging a dock splitter does not restart the
pipelines every frame."""

from __future__ import annotations

import time

import numpy as np

from explorer.ui.state import AppState

MIN_RENDER_SIZE = 16
MAX_RENDER_SIZE = 2048
RESIZE_SETTLE_S = 0.15
"""Re-render at a new view size once resizing pauses this long."""
LAYOUT_FRAMES = 2
"""Frames before the View panel's size is trusted (the dock layout settles in them)."""


class ViewSizeFollower:
    """Keeps ``state.settings``' width and height at the View panel's size."""

    def __init__(self) -> None:
        self.pending: tuple | None = None
        """(size, time.monotonic()) of a new size not applied yet."""

    def follow(self, state: AppState) -> bool:
        """Apply the View panel's size when due; False while the size is not known yet
        (the first frames), so that the first run already has the right size."""
        rt = state.runtime
        if not state.follow_view_size:
            return True
        vw, vh = rt.view.view_size
        if rt.frame.frame_index < LAYOUT_FRAMES:
            return False
        if vw < MIN_RENDER_SIZE or vh < MIN_RENDER_SIZE:
            return True                 # the view panel is hidden: keep the stored size
        size = (int(np.clip(vw * state.render_scale, MIN_RENDER_SIZE, MAX_RENDER_SIZE)),
                int(np.clip(vh * state.render_scale, MIN_RENDER_SIZE, MAX_RENDER_SIZE)))
        current = (state.settings.width, state.settings.height)
        if size == current:
            self.pending = None
            return True
        now = time.monotonic()
        if rt.frame.result is None or (self.pending and self.pending[0] == size
                                       and now - self.pending[1] >= RESIZE_SETTLE_S):
            state.update(width=size[0], height=size[1])
            self.pending = None
        elif not self.pending or self.pending[0] != size:
            self.pending = (size, now)
        return True
