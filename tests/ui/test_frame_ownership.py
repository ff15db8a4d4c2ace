"""Who keeps a frame alive in the window: only what shows it. The compositor, the view
composer's difference scale and the lesson figures hold no frame past the picture they
made (a frame kept with its propagation steps is hundreds of MiB at 64³)."""

from __future__ import annotations

import gc
import weakref
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest

from explorer.gl.program import ProgramCache
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.ui.figures import FigureContext
from explorer.ui.overlays.compositor import Compositor
from explorer.ui.state import OverlayState
from explorer.ui.view_composer import ViewComposer
from explorer.ui.weak_version import WeakVersion

CORNELL = Settings(scene="cornell", grid_size=8, iterations=3, rsm_size=32, width=48,
                   height=36)


def _freed(ref: weakref.ref) -> bool:
    gc.collect()
    return ref() is None


def test_a_weak_version_matches_its_parts_and_nothing_once_one_is_freed():
    class Frame:
        pass

    frame, other = Frame(), Frame()
    version = WeakVersion((frame, 3, "slice", (1, 2)), (int, str, tuple))
    assert version.matches((frame, 3, "slice", (1, 2)))
    assert not version.matches((other, 3, "slice", (1, 2)))
    assert not version.matches((frame, 4, "slice", (1, 2)))
    assert not version.matches((frame, 3, "slice"))
    held = [1, 2]                       # no weak reference can name a list: held
    assert WeakVersion((held,), ()).matches((held,))
    assert not WeakVersion((held,), ()).matches(([1, 2],))
    ref = weakref.ref(frame)
    del frame
    assert _freed(ref), "the version kept its frame alive"
    assert not version.matches((Frame(), 3, "slice", (1, 2)))


def test_the_compositor_keeps_no_frame_the_view_has_left(ctx):
    """A frame drawn with the light in flight and the VPLs, then another frame: the
    first is freed (its slice field and VPL upload versions held it, with its steps)."""
    with Pipeline(CORNELL, ctx=ctx) as pipeline:
        result = pipeline.run(CORNELL, keep_steps=True)
        compositor = Compositor(ctx)
        try:
            shown = replace(result)            # a frame of its own, the same arrays
            overlays = OverlayState(slice=True, slice_quantity="in-flight", vpls=True)
            texture = pipeline.final_texture.glo
            compositor.compose("A", shown, texture, False, overlays)
            assert compositor.notes["A"] == []
            drawn = compositor.compositions
            compositor.compose("A", shown, texture, False, overlays)
            assert compositor.compositions == drawn, "an unchanged request redrew"
            ref = weakref.ref(shown)
            del shown
            compositor.compose("A", result, texture, False, OverlayState())
            assert _freed(ref), "the compositor kept a frame the view no longer shows"
            compositor.compose("A", replace(result), texture, False, overlays)
            assert compositor.compositions == drawn + 2 and compositor.notes["A"] == []
        finally:
            compositor.release()


def test_the_difference_scale_keeps_no_frame(ctx):
    class Frame:
        def __init__(self, value: float) -> None:
            self.direct = np.full((4, 4, 3), value, np.float32)

    a, b = Frame(2.0), Frame(1.0)
    display = SimpleNamespace(exposure=1.0, indirect_only=False)
    programs = ProgramCache(ctx)
    composer = ViewComposer(ctx, programs)
    try:
        top = composer._auto_top(SimpleNamespace(result=a), SimpleNamespace(result=b),
                                 display, display, "direct")
        assert top == pytest.approx(1.0, rel=1e-5)
        ref = weakref.ref(b)
        del b
        assert _freed(ref), "the difference scale's cache kept side B's frame"
        again = composer._auto_top(SimpleNamespace(result=a),
                                   SimpleNamespace(result=Frame(1.5)), display, display,
                                   "direct")
        assert again == pytest.approx(0.5, rel=1e-5)
    finally:
        composer.release()
        programs.release()


def test_the_lesson_figures_read_the_apps_frames_only_while_shown():
    class Frame:
        pass

    a = Frame()
    state = SimpleNamespace(runtime=SimpleNamespace(
        frame=SimpleNamespace(result=a, compare_result=None)), comparing=False)
    context = FigureContext()
    with context.showing(state) as shown:
        assert shown.results == (a,)
    assert context.results == ()
    ref = weakref.ref(a)
    del a, state
    assert _freed(ref), "the figure context kept the frame past the step"


def test_a_window_frame_keeps_the_steps_of_the_finest_level_only(gl_context, ctx):
    """The in-flight overlays read level 0's steps; with two cascades the second level's
    would double what the frame on screen holds."""
    from explorer.ui.controller import PipelineController
    from explorer.ui.state import AppState

    controller = PipelineController(gl_context, Pipeline)
    try:
        state = AppState(settings=CORNELL.with_changes(cascades=2))
        state.follow_view_size = False
        state.overlays.slice, state.overlays.slice_quantity = True, "in-flight"
        for _ in range(2000):
            if not controller.update(state, 50.0).active:
                break
        result = state.runtime.frame.result
        assert len(result.cascades) == 2
        assert len(result.steps) == CORNELL.iterations + 1
        assert result.cascades[1].steps is None
    finally:
        controller.release()


def test_the_views_white_share_note_keeps_no_frame():
    """The note "much of B shows white" is measured once per frame and display; the
    measurement's cache held a 64³ frame with its steps after the view had moved on."""
    from explorer.ui.panels.view import washed_out
    from explorer.ui.picture import SideDisplay

    class Frame:
        def __init__(self, level: float) -> None:
            self.final_image = np.full((4, 4, 3), level, np.float32)
            self.indirect = self.final_image

    def state_showing(frame) -> SimpleNamespace:
        display = SideDisplay(exposure=1.0, scale=1.0, tone_map="linear-clip",
                              indirect_only=False)
        frames = SimpleNamespace(pictures={"B": SimpleNamespace(result=frame)},
                                 displays={"B": display})
        return SimpleNamespace(runtime=SimpleNamespace(frame=frames),
                               expose_sides_separately=False, view_mode="split")

    white = Frame(5.0)
    assert washed_out(state_showing(white), "B") != ""
    ref = weakref.ref(white)
    del white
    assert _freed(ref), "the white-share cache kept the frame"
    assert washed_out(state_showing(Frame(0.1)), "B") == ""


def _measure_to_the_end(service, ctx) -> None:
    """Ask the Error panel's service for a measurement and advance it until it is done."""
    service.measure()
    for _ in range(2000):
        service.advance(ctx, 0.0)
        if not service.running:
            return
    raise AssertionError("the measurement did not finish in 2000 advances")


def test_the_error_panels_pipeline_is_given_back_once_idle(ctx, monkeypatch):
    """The measuring pipeline holds a frame's grids at the grid shown; it goes once no
    measurement has run for PIPELINE_IDLE_S, and the next measurement makes a new one."""
    from explorer.truth.progressive import Measurement
    from explorer.ui.panels import error

    clock = [1000.0]
    monkeypatch.setattr(error.time, "monotonic", lambda: clock[0])
    state = SimpleNamespace(settings=CORNELL)
    service = error.ErrorService(state)
    service.measurement = Measurement(size=24, rsm_size=16, reference="unoccluded")
    try:
        _measure_to_the_end(service, ctx)
        assert service.result_for() is not None and service.pipeline is not None
        service.advance(ctx, 0.0)                     # idle from now
        clock[0] += error.PIPELINE_IDLE_S - 1.0
        service.advance(ctx, 0.0)
        assert service.pipeline is not None           # not yet
        clock[0] += 2.0
        service.advance(ctx, 0.0)
        assert service.pipeline is None and service.result_for() is not None
        state.settings = CORNELL.with_changes(iterations=2)
        _measure_to_the_end(service, ctx)
        assert service.result_for().settings.iterations == 2
        clock[0] += error.PIPELINE_IDLE_S - 1.0       # idle again, counted afresh
        service.advance(ctx, 0.0)
        assert service.pipeline is not None
    finally:
        service.release()


def test_the_soak_gives_the_idle_error_pipeline_back_in_the_frame_it_asks(ctx, monkeypatch):
    """``idle_release_s`` 0 (what the soak sets for one frame, as for the controller's idle
    sides): the pipeline of a finished measurement goes in that same advance, so the GL
    counts after a step do not depend on how long the step took."""
    from explorer.truth.progressive import Measurement
    from explorer.ui.panels import error

    monkeypatch.setattr(error.time, "monotonic", lambda: 1000.0)
    service = error.ErrorService(SimpleNamespace(settings=CORNELL))
    service.measurement = Measurement(size=24, rsm_size=16, reference="unoccluded")
    try:
        _measure_to_the_end(service, ctx)
        assert service.pipeline is not None
        service.idle_release_s = 0.0
        service.advance(ctx, 0.0)
        assert service.pipeline is None and service.result_for() is not None
    finally:
        service.release()
