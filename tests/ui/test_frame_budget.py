"""The window's frame budget against issue #32's 50 ms frame: a drag's budget and the
quiet one leave a frame within the target, and the frame that shows a finished job keeps
what its drawing costs more free for the units that finish it."""

from __future__ import annotations

import time

import pytest

from explorer.lpv.job import FINAL_STAGE
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.ui import frame_pacing, previews
from explorer.ui.controller import PipelineController
from explorer.ui.frame_budget import (
    FRAME_TARGET_MS,
    QUIET_BUDGET_MS,
    FrameBudget,
    ResultDrawing,
)
from explorer.ui.state import AppState


def test_a_drag_frame_with_its_drawing_is_inside_the_frame_target():
    for drawing_ms in (5.0, 15.0, 30.0):
        assert frame_pacing.drag_budget_ms(drawing_ms) + drawing_ms == pytest.approx(
            FRAME_TARGET_MS - frame_pacing.DRAG_MARGIN_MS)
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


# --- through the controller ---------------------------------------------------------------
SMALL = Settings(scene="cornell", grid_size=8, iterations=6, rsm_size=32, width=48,
                 height=36)


@pytest.fixture
def controller(gl_context, ctx):
    control = PipelineController(gl_context, Pipeline)
    yield control
    control.release()


def _settled(controller, state, budget_ms: float, units: list[str]) -> list[list[str]]:
    """Update until nothing is left to do; the stages of the units each update ran (A's
    pipeline records them in ``units``)."""
    per_update = []
    for _ in range(2000):
        before = len(units)
        status = controller.update(state, budget_ms)
        per_update.append(units[before:])
        if not status.active:
            return per_update
    raise AssertionError("the controller never settled")


def _recorded(pipe) -> list[str]:
    """Make ``pipe`` record the stage of every unit its jobs run."""
    units: list[str] = []
    stage_work = pipe.stage_work

    def recorded(stage, job):
        for value in stage_work(stage, job):
            units.append(stage)
            yield value
        units.append(stage)             # the last unit (the generator's end)

    pipe.stage_work = recorded
    return units


def test_the_units_finishing_a_job_leave_the_finished_frames_drawing_free(controller):
    state = AppState(settings=SMALL)
    state.follow_view_size = False
    _settled(controller, state, 50.0, [])
    units = _recorded(controller.sides["A"].pipeline)
    state.set_corrections(propagation_4pi=False)
    together = _settled(controller, state, 1e6, units)      # nothing reserved yet
    assert any(ran.count(FINAL_STAGE) > 1 for ran in together)
    controller.result_drawing.note(1.0, finished=False)
    controller.result_drawing.note(1e7, finished=True)     # a finished frame draws long
    state.set_corrections(propagation_4pi=True)
    apart = _settled(controller, state, 1e6, units)
    finishing = [ran for ran in apart if FINAL_STAGE in ran]
    # each of the last stage's units in a frame of its own, whatever the budget
    assert len(finishing) == 3 and all(ran == [FINAL_STAGE] for ran in finishing)
    assert controller.sides["A"].result.stages_run[-1] == FINAL_STAGE


def test_a_frame_whose_preview_leaves_no_room_runs_no_unit(controller, monkeypatch):
    state = AppState(settings=SMALL.with_changes(iterations=20))
    state.follow_view_size = False
    _settled(controller, state, 50.0, [])
    units = _recorded(controller.sides["A"].pipeline)
    controller.preview_interval_s = 1e-9                   # a preview after every step ...
    monkeypatch.setattr(previews, "PREVIEW_SHARE", 1e9)    # ... whatever it costs
    monkeypatch.setattr(previews, "FINISH_SOON_S", 0.0)
    pipe = controller.sides["A"].pipeline
    show_preview = pipe.show_preview

    def preview(job, scale=1.0, injected=False):
        units.append("preview")
        return show_preview(job, scale, injected=injected)

    pipe.show_preview = preview
    state.set_corrections(propagation_4pi=False)
    shown, ran_after = 0, []
    for _ in range(2000):
        before, previews_before = len(units), controller.sides["A"].previews
        status = controller.update(state, 1e-3)            # less than any unit
        if controller.sides["A"].previews != previews_before:
            shown += 1
            ran = units[before:]
            # the units after the preview (the job's first preview follows the unit that
            # made it possible, in the same frame; the later ones come at a turn's start)
            ran_after.append(len(ran) - ran.index("preview") - 1)
        if not status.active:
            break
    assert shown >= 3 and ran_after == [0] * shown
