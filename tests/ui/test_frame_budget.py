"""The window's frame budget against issue #32's 50 ms frame: a drag's budget and the
quiet one leave a frame within the target, and the frame that shows a finished job keeps
what its drawing costs more free for the units that finish it."""

from __future__ import annotations

import time

from explorer.ui import frame_pacing
from explorer.ui.frame_budget import (
    FRAME_TARGET_MS,
    QUIET_BUDGET_MS,
    FrameBudget,
    ResultDrawing,
)


def test_a_drag_frame_with_its_drawing_is_the_frame_target():
    for drawing_ms in (5.0, 15.0, 30.0):
        assert frame_pacing.drag_budget_ms(drawing_ms) + drawing_ms == FRAME_TARGET_MS
    assert frame_pacing.drag_budget_ms(1e3) == frame_pacing.MIN_DRAG_BUDGET_MS
    assert QUIET_BUDGET_MS < FRAME_TARGET_MS


def test_a_finished_frame_reserves_what_its_drawing_costs_more():
    drawing = ResultDrawing()
    drawing.note(20.0, finished=True)
    assert drawing.extra_ms == 0.0               # nothing to compare with yet
    drawing.note(12.0, finished=False)
    assert drawing.extra_ms == 8.0
    drawing.note(32.0, finished=True)            # smoothed: 20 + 0.3 · 12
    assert abs(drawing.extra_ms - (23.6 - 12.0)) < 1e-9
    drawing.note(60.0, finished=False)           # plain frames costlier: nothing reserved
    assert drawing.extra_ms == 0.0


def test_the_finishing_units_get_the_frame_budget_less_the_reserve():
    budget = FrameBudget(time.perf_counter(), 100.0, 30.0, None)
    assert 19.0 < budget.finishing_left(10.0) <= 20.0       # of the frame budget, not 100
    assert budget.finishing_left(50.0) == 0.0
