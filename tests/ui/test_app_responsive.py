"""The window's frame loop under Xvfb: an idle window draws nothing and runs no stage
until input or a change arrives; a camera drag (imgui mouse events on the view) renders
at a reduced size and the full size follows when it ends; a held slider over a pipeline
setting counts as such a move."""

from __future__ import annotations

from collections import Counter

import pytest

from explorer.ui.state import AppState

pytest.importorskip("glfw")
from test_app_window import (  # noqa: E402,F401
    _PROBLEM,
    TINY,
    _app,
    config_home,
    needs_pipeline,
)

pytestmark = [pytest.mark.skipif(_PROBLEM is not None, reason=str(_PROBLEM)),
              pytest.mark.usefixtures("config_home"), needs_pipeline]


def _stages_begun(app) -> Counter:
    return Counter(app.controller.stage_runs("A"))


def test_an_idle_window_draws_nothing_until_something_changes():
    state = AppState(settings=TINY)
    state.follow_view_size = False
    app = _app(state, wait_when_idle=True, idle_timeout_s=0.01)
    try:
        assert app.settle()
        for _ in range(4):            # the frames imgui draws after the last change
            app.frame()
        drawn, stages = app.state.runtime.frame.frame_index, _stages_begun(app)
        skipped = app.frames_skipped
        for _ in range(20):
            assert app.frame()
        assert app.state.runtime.frame.frame_index == drawn, "an idle window drew"
        assert app.frames_skipped - skipped == 20
        assert _stages_begun(app) == stages
        app.state.update(exposure=2.0)            # a change: drawn at once, no stage runs
        app.frame()
        assert app.state.runtime.frame.frame_index == drawn + 1
        assert app.state.runtime.frame.displays["A"].exposure == 2.0
        assert _stages_begun(app) == stages
        app.window._on_event()                   # any input event draws too
        app.frame()
        assert app.state.runtime.frame.frame_index == drawn + 2
    finally:
        app.close()


def _drag(app) -> list:
    """Press the mouse over the view and orbit a few frames (not released); the render
    sizes of those frames. Each event is counted as glfw's callback would (a window that
    waits for events wakes for it)."""
    from imgui_bundle import imgui

    x0, y0, x1, y1 = app.state.runtime.view.view_rect
    scale = imgui.get_io().display_framebuffer_scale.x or 1.0
    x, y = (x0 + x1) / 2 / scale, (y0 + y1) / 2 / scale
    io = imgui.get_io()
    io.add_mouse_pos_event(x, y)
    app.window._on_event()
    app.frame()
    io.add_mouse_button_event(0, True)
    app.window._on_event()
    app.frame()
    app.controller.drag.scale = 0.5        # as if a camera frame had been timed
    sizes = []
    for step in range(1, 8):              # the drag: the camera orbits each frame
        io.add_mouse_pos_event(x + 6 * step, y)
        app.window._on_event()
        app.frame()
        assert app.state.runtime.view.interaction.held
        sizes.append(app.state.runtime.frame.result.direct.shape[:2])
    return sizes


def test_a_drag_on_the_view_renders_smaller_then_refines():
    from imgui_bundle import imgui

    state = AppState(settings=TINY)
    state.follow_view_size = False
    app = _app(state, width=1200, height=800)
    try:
        assert app.settle()
        full = app.state.runtime.frame.result.direct.shape[:2]
        io = imgui.get_io()
        sizes = _drag(app)
        camera = app.state.settings.camera
        assert camera is not None
        assert any(size[0] < full[0] and size[1] < full[1] for size in sizes), sizes
        io.add_mouse_button_event(0, False)
        assert app.settle()                   # the drag ended: the full size follows
        assert not app.state.runtime.view.interaction.held
        assert app.state.runtime.frame.result.direct.shape[:2] == full
        assert app.state.runtime.frame.result.camera.eye == pytest.approx(camera[0])
        assert [m.text for m in app.state.messages if m.level == "error"] == []
    finally:
        app.close()


def test_a_released_drag_refines_without_waiting_for_the_idle_timeout():
    """An idle loop waits for events, but not past the moment a camera move settles (its
    full-size frame starts then), and never while a job runs."""
    from imgui_bundle import imgui

    from explorer.ui.frame_pacing import INTERACTION_SETTLE_S

    state = AppState(settings=TINY)
    state.follow_view_size = False
    app = _app(state, width=1200, height=800, wait_when_idle=True, idle_timeout_s=30.0)
    try:
        assert app.settle()
        full = app.state.runtime.frame.result.direct.shape[:2]
        _drag(app)
        imgui.get_io().add_mouse_button_event(0, False)
        app.window._on_event()
        app.frame()                            # the release: the camera settles now
        assert not app.state.runtime.view.interaction.held
        assert app.idle_timeout() <= INTERACTION_SETTLE_S + 0.02
        waits = []
        for _ in range(500):
            app.frame()
            waits.append(app.last_wait_s)
            if app.state.runtime.frame.result.direct.shape[:2] == full and not app.status.active:
                break
        assert app.state.runtime.frame.result.direct.shape[:2] == full
        assert max(waits) <= INTERACTION_SETTLE_S + 1.0, waits     # not the 30 s timeout
    finally:
        app.close()


def test_a_held_slider_that_changes_the_pipelines_counts_as_a_move(monkeypatch):
    """A slider dragged over a setting the pipelines run (the light's flux) counts as a
    move while it is held, so that its jobs render at the drag's size and finish before
    the next starts; a display field's (the exposure) does not, nor a change made with no
    widget held."""
    from imgui_bundle import imgui

    from explorer.ui import frame_pacing

    state = AppState(settings=TINY)
    interaction = state.runtime.view.interaction
    held = [True]
    monkeypatch.setattr(imgui, "is_any_item_active", lambda: held[0])
    before = state.settings
    state.update(exposure=2.0)
    frame_pacing.note_setting_drag(state, before)
    assert interaction.moved_at < 0 and not frame_pacing.interacting(state)
    before = state.settings
    state.update(light_flux=(before.light_flux or 1.0) * 1.1)
    frame_pacing.note_setting_drag(state, before)
    assert frame_pacing.interacting(state)
    interaction.moved_at = -1e9
    held[0] = False
    before = state.settings
    state.update(light_flux=before.light_flux * 1.1)
    frame_pacing.note_setting_drag(state, before)
    assert not frame_pacing.interacting(state)



def test_a_move_that_settled_during_a_frame_lets_no_wait_follow():
    """The loop may wait for events only when nothing is due: a frame whose update ran
    while the camera moved, the move settled since, has the full-size frame due (it used
    to wait the whole idle timeout, half a second after a drag)."""
    from explorer.ui.frame_pacing import may_wait

    assert may_wait(False, False, False)
    assert not may_wait(False, True, False)      # settled during this frame
    assert not may_wait(False, False, True)
    assert not may_wait(True, False, False)
