"""A job's first picture in the window (issue #32 item 3: within 150 ms of a change at
64³ on llvmpipe): on a large grid the injected light as soon as the injection is done,
labelled "injected light only" (explorer/ui/previews.py ``INJECTED_PREVIEW_CELLS``), and
every first preview in the frame whose unit made it possible rather than the next one
(explorer/ui/controller.py ``_first_preview_due``). No timing here: which picture comes,
after which units, and what it shows."""

from __future__ import annotations

import numpy as np
import pytest

from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.ui.controller import PipelineController
from explorer.ui.panels.view import progress_label
from explorer.ui.picture import Stamp
from explorer.ui.previews import INJECTED_PREVIEW_CELLS
from explorer.ui.state import AppState

SMALL = Settings(scene="cornell", grid_size=8, iterations=6, rsm_size=32, width=48,
                 height=36)
ONE_UNIT_MS = 0.01
"""Less than any unit: each update does one unit."""


@pytest.fixture
def controller(gl_context, ctx):
    control = PipelineController(gl_context, Pipeline)
    yield control
    control.release()


def _state(**changes) -> AppState:
    state = AppState(settings=SMALL.with_changes(**changes))
    state.follow_view_size = False
    return state


def _settle(controller, state, budget_ms=50.0) -> None:
    for _ in range(2000):
        if not controller.update(state, budget_ms).active:
            return
    raise AssertionError("the controller never settled")


def _recorded(controller) -> list[str]:
    """Side A's units and previews in the order they ran: a unit's stage, "preview"."""
    pipe = controller.sides["A"].pipeline
    events: list[str] = []
    stage_work, show_preview = pipe.stage_work, pipe.show_preview

    def work(stage, job):
        for value in stage_work(stage, job):
            events.append(stage)
            yield value
        events.append(stage)

    def preview(job, scale=1.0, injected=False):
        events.append("preview")
        return show_preview(job, scale, injected=injected)

    pipe.stage_work, pipe.show_preview = work, preview
    return events


def _first_preview(controller, state, budget_ms=ONE_UNIT_MS):
    """Update until side A publishes a preview: (its stamp, the events before it)."""
    events = _recorded(controller)
    for _ in range(2000):
        status = controller.update(state, budget_ms)
        picture = state.runtime.frame.pictures["A"]
        if status.published and not picture.stamp.final:
            return picture.stamp, events[:events.index("preview")]
        assert status.active, "the job finished with no preview"
    raise AssertionError("no preview came")


def test_a_large_grids_first_preview_is_its_injected_light(controller, gl_context):
    """The grid set larger: the first preview comes once the injection is done, before the
    propagation's first step, labelled; it is the injected light (the one-shot frame of
    no propagation step, iterations 0), and the finished frame is the one-shot frame."""
    controller.injected_preview_cells = 16 ** 3       # 16³ counts as a large grid here
    controller.first_preview_scale = controller.preview_scale = 1.0     # full size
    state = _state()
    _settle(controller, state)
    state.update(grid_size=16)
    stamp, before = _first_preview(controller, state)
    assert stamp.injected and stamp.done == 0
    assert "inject" in before and "propagate" not in before, before
    picture = state.runtime.frame.pictures["A"]
    assert "injected light only" in progress_label("propagating 0/6", picture)
    direct, indirect, _ = picture.read()
    with Pipeline(state.settings, ctx=gl_context) as once:
        injected = once.run(state.settings.with_changes(iterations=0), need_audit=False)
    assert np.abs(injected.indirect).max() > 0.0
    for got, want in ((direct, injected.direct), (indirect, injected.indirect)):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-6 * max(
            float(np.abs(want).max()), 1e-30))
    _settle(controller, state, ONE_UNIT_MS)
    result = state.runtime.frame.result
    with Pipeline(result.settings, ctx=gl_context) as once:
        expected = once.run(result.settings, need_audit=False)
    assert np.array_equal(result.indirect, expected.indirect)


def test_an_injection_toggle_on_a_large_grid_shows_the_new_injection_first(controller):
    controller.injected_preview_cells = 8 ** 3
    state = _state()
    _settle(controller, state)
    state.set_corrections(injection_pi=not state.settings.corrections.injection_pi)
    stamp, before = _first_preview(controller, state)
    assert stamp.injected and "propagate" not in before, before


def test_a_small_grid_or_a_propagation_toggle_waits_for_the_first_step(controller):
    """Below INJECTED_PREVIEW_CELLS the first preview is the first step's; so is it on a
    large grid when the injection did not run (a propagation switch: the injected light
    would show nothing of the change)."""
    assert 32 ** 3 < INJECTED_PREVIEW_CELLS <= 64 ** 3
    state = _state()
    _settle(controller, state)
    state.update(grid_size=16)
    stamp, before = _first_preview(controller, state)
    assert not stamp.injected and stamp.done >= 1 and "propagate" in before
    controller.injected_preview_cells = 8 ** 3
    _settle(controller, state)
    state.set_corrections(propagation_4pi=not state.settings.corrections.propagation_4pi)
    stamp, before = _first_preview(controller, state)
    assert not stamp.injected and stamp.done >= 1 and "inject" not in before
    assert "injected light only" not in progress_label(
        "propagating 1/6", state.runtime.frame.pictures["A"])


def test_a_drags_jobs_show_no_injected_light(controller):
    """A drag's reduced jobs follow one another: an injected-light picture of each would
    flash darker between their finished ones."""
    controller.injected_preview_cells = 8 ** 3
    state = _state()
    _settle(controller, state)
    state.update(light_flux=(state.settings.light_flux or 1.0) * 1.1)
    for _ in range(200):
        status = controller.update(state, ONE_UNIT_MS, interacting=True)
        picture = state.runtime.frame.pictures["A"]
        assert not (status.published and picture.stamp.injected)
        if not status.active:
            break


def test_the_first_preview_comes_in_the_frame_of_its_step(controller):
    """Within one update the job stops at its first picture, the preview is taken, and the
    job goes on while the frame has room: with a budget larger than the whole job, the one
    update shows a preview of the first step, then the finished frame (before, the update
    ran the job to its end with no preview: a preview came only at a turn's start)."""
    state = _state()
    _settle(controller, state)
    state.set_corrections(propagation_4pi=not state.settings.corrections.propagation_4pi)
    events = _recorded(controller)
    status = controller.update(state, 1e6)
    side = controller.sides["A"]
    assert side.job is None and status.finished
    assert side.previews == 1
    at = events.index("preview")
    assert events[at - 1] == "propagate" and "gather" in events[at + 1:], events
    assert state.runtime.frame.pictures["A"].stamp.final


def test_a_first_preview_that_does_not_fit_the_frame_comes_first_in_the_next(controller):
    """What the job's first preview cost last time does not fit what the frame has left:
    the job stops at its picture and the frame ends there (it would run past the 50 ms
    frame otherwise); the next frame takes the preview before any unit."""
    state = _state()
    _settle(controller, state)
    side = controller.sides["A"]
    side.first_preview_ms = 1e9                  # what the last first preview cost
    state.set_corrections(propagation_4pi=not state.settings.corrections.propagation_4pi)
    events = _recorded(controller)
    controller.update(state, 1e6)
    assert side.previews == 0 and side.job is not None
    assert side.job.progress.stage == "propagate" and side.job.progress.done >= 1
    assert events and "preview" not in events
    ran = len(events)
    status = controller.update(state, 1e6)
    assert side.previews == 1 and status.published
    assert events[ran] == "preview", events[ran:]


def test_after_a_first_preview_only_a_unit_timed_at_this_size_goes_on(controller):
    """The frame of a first preview is drawn: the job goes on in it only with a unit timed
    before at this grid size. At a new size (the grid set larger) the propagation's start
    waits for the next frame, whatever the budget; at a size run before, it goes on."""
    controller.injected_preview_cells = 8 ** 3
    state = _state()
    _settle(controller, state)
    state.update(grid_size=16)
    events = _recorded(controller)
    for _ in range(50):
        controller.update(state, 1e6)
        if "preview" in events:
            break
    assert events[-1] == "preview" and "propagate" not in events, events
    _settle(controller, state)
    state.set_corrections(injection_pi=not state.settings.corrections.injection_pi)
    events.clear()
    controller.update(state, 1e6)
    assert "preview" in events and "propagate" in events[events.index("preview"):], events


def test_a_drag_frame_runs_as_before(controller):
    """A drag's job that fits its frame shows its finished picture alone (no first preview
    taken in the middle of it)."""
    state = _state()
    _settle(controller, state)
    state.update(light_flux=(state.settings.light_flux or 1.0) * 1.1)
    status = controller.update(state, 1e6, interacting=True)
    assert status.finished and controller.sides["A"].previews == 0


def test_the_label_names_a_preview_of_the_injected_light():
    class Shown:
        size = (240, 135)
        stamp = Stamp(3, False, 0, 16, injected=True)

    assert progress_label("propagating 0/16", Shown()) == (
        "preview 240×135, injected light only · propagating 0/16")
    Shown.stamp = Stamp(4, False, 2, 16)
    assert progress_label("propagating 2/16", Shown()) == (
        "preview 240×135 · propagating 2/16")
