"""The time a frame of the window gives the pipelines: the frame budget, the longer quiet
budget once the user leaves the window alone (cut back as soon as input arrives), and the
render size a camera drag can afford (the largest of :data:`DRAG_SCALES` whose measured
camera frame fits the drag's budget)."""

from __future__ import annotations

import time
from collections.abc import Callable

from explorer.lpv.cache_keys import downstream

FRAME_TARGET_MS = 50.0
"""The longest a frame should take while the user interacts (issue #32): a drag's frames
aim a little inside it (explorer/ui/frame_pacing.py ``DRAG_FPS``, ``DRAG_MARGIN_MS``), and
a quiet frame's longer budget stays under it."""
QUIET_AFTER_S = 0.15
"""No input for this long: the user is watching, the pipelines get :data:`QUIET_BUDGET_MS`
a frame ..."""
QUIET_BUDGET_MS = 45.0
"""... (or the frame budget if larger) instead of the frame budget, so that fewer frames
share the work; the shell's ``input_pending`` is asked between units and input brings
the budget back at once. A quiet frame mostly draws nothing (a job with nothing new to
show), so this keeps it under :data:`FRAME_TARGET_MS` with room for a unit's
misestimate: input that arrives in the middle of one waits no longer than that."""
FINISHING_STAGES = frozenset(downstream("propagate")[1:])
"""The stages after the propagation (gather, fog, display): a job in one of them is
about to publish its finished frame, which is drawn, so its frame gets no quiet budget."""
DRAG_SCALES = (1.0, 0.5, 0.25)
"""Render-size factors tried while the camera is dragged, largest first."""
FIRST_DRAG_SCALE = 0.5
"""Used until a camera-only frame has been timed."""


class FrameBudget:
    """One update's time: ``ms`` from ``start``, back to ``base_ms`` once
    ``input_pending()`` says input arrived (asked only while more than the base is left
    to spend)."""

    def __init__(self, start: float, ms: float, base_ms: float,
                 input_pending: Callable[[], bool] | None) -> None:
        self.start, self.ms, self.base_ms = start, ms, base_ms
        self.input_pending = input_pending

    @classmethod
    def for_frame(cls, budget_ms: float, *, interacting: bool, drag_budget_ms: float,
                  quiet_s: float, quiet_budget_ms: float,
                  input_pending: Callable[[], bool] | None) -> FrameBudget:
        """The budget of a frame starting now: a drag's frame gets at least the drag
        budget; a quiet one (no input for :data:`QUIET_AFTER_S`) ``quiet_budget_ms``."""
        if interacting:
            budget_ms = max(budget_ms, drag_budget_ms)
        base_ms = budget_ms
        if not interacting and quiet_s >= QUIET_AFTER_S:
            budget_ms = max(budget_ms, quiet_budget_ms)
        return cls(time.perf_counter(), budget_ms, base_ms, input_pending)

    @property
    def quiet(self) -> bool:
        """More than the frame budget is on offer (a quiet frame)."""
        return self.ms > self.base_ms

    def to_base(self) -> None:
        """Keep to the frame budget from now on (the frame is drawn anyway)."""
        self.ms = min(self.ms, self.base_ms)

    def left(self) -> float:
        """Milliseconds left (negative once overspent)."""
        if self.ms > self.base_ms and self.input_pending is not None and self.input_pending():
            self.ms = self.base_ms
        return self.ms - (time.perf_counter() - self.start) * 1e3

    def base_left(self) -> float:
        """Milliseconds left of the frame budget alone."""
        return self.base_ms - (time.perf_counter() - self.start) * 1e3

    def finishing_left(self, extra_ms: float) -> float:
        """What the units that finish a job may take now: the frame budget left less
        ``extra_ms``, what the frame showing the finished frame draws more
        (:class:`ResultDrawing`); at least 0."""
        return max(self.base_left() - extra_ms, 0.0)


RESULT_SMOOTHING = 0.3
"""Weight of the latest frame in :class:`ResultDrawing`'s running measure."""


class ResultDrawing:
    """What a frame that shows a job's finished frame costs over a plain drawn frame: its
    snapshot, the panels built anew for the new result (the View panel's picture, the
    plots) and the drawing of the new picture. The controller keeps that much of the frame
    budget free for the units that finish a job (``Job.advance``'s ``finishing_ms``), so
    that such a frame stays within the budget and its drawing."""

    def __init__(self) -> None:
        self.extra_ms = 0.0
        """The running measure (0 until a finished frame has been drawn)."""
        self._plain_ms: float | None = None
        self._result_ms: float | None = None

    def note(self, drawing_ms: float, finished: bool) -> None:
        """A drawn frame took ``drawing_ms`` besides the pipelines' units (its snapshots
        included); ``finished``: it showed a finished frame."""
        last = self._result_ms if finished else self._plain_ms
        value = drawing_ms if last is None else last + RESULT_SMOOTHING * (drawing_ms - last)
        if finished:
            self._result_ms = value
        else:
            self._plain_ms = value
        if self._result_ms is not None and self._plain_ms is not None:
            self.extra_ms = max(self._result_ms - self._plain_ms, 0.0)


class DragSizer:
    """The render-size factor of a camera drag, chosen from the camera-only frames timed
    so far: the largest of :data:`DRAG_SCALES` whose frame fits the drag budget (shared
    by the sides on screen). A scale not timed yet is predicted from the nearest one
    timed, by its pixels."""

    def __init__(self) -> None:
        self.scale = FIRST_DRAG_SCALE
        self.camera_ms: dict[float, float] = {}
        """Drag scale -> milliseconds of the last camera-only frame at about that scale."""
        self.camera_ms_per_pixel: float | None = None
        """Measured cost of the last camera-only frame per pixel."""

    def measure(self, pixels: int, full_pixels: int, elapsed_ms: float,
                side_budget_ms: float) -> float:
        """Record a camera-only frame of ``pixels`` that took ``elapsed_ms``; returns the
        scale chosen for the next drag."""
        full = max(full_pixels, 1)
        scale = min(DRAG_SCALES, key=lambda k: abs(k * k * full - pixels))
        self.camera_ms[scale] = elapsed_ms
        self.camera_ms_per_pixel = elapsed_ms / max(pixels, 1)

        def predicted(k: float) -> float:
            if k in self.camera_ms:
                return self.camera_ms[k]
            nearest = min(self.camera_ms, key=lambda m: abs(m - k))
            return self.camera_ms[nearest] * (k / nearest) ** 2

        fits = [k for k in DRAG_SCALES if predicted(k) <= side_budget_ms]
        self.scale = fits[0] if fits else DRAG_SCALES[-1]
        return self.scale
