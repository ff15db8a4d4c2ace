"""A lesson figure drawn once (explorer/ui/figure_cache.py), in the one-figure window under
Xvfb: an unchanged figure is drawn live until it settles and then shown from its picture
(the same pixels), drawn again when its inputs or the frames it plots change, live while
hovered or playing, and its picture released when the page changes. Draws are counted,
not timed."""

from __future__ import annotations

import moderngl
import numpy as np
import pytest
from window_cases import display_problem

from explorer.ui.figures import FIGURES, make_figure

_PROBLEM = display_problem()
pytestmark = pytest.mark.skipif(_PROBLEM is not None, reason=str(_PROBLEM))
FRAMES = 10


@pytest.fixture
def window():
    from explorer.ui.figures.harness import FigureWindow

    win = FigureWindow(900, 1100, visible=False, cached=True)
    yield win
    win.close()


def _frames(window, spec, frames: int = FRAMES) -> np.ndarray:
    """``frames`` frames of ``spec``; the figure's pixels in the last."""
    return window.render(spec, frames=frames)


def _state(window, spec):
    """The figure instance's interactive state (what the reader's drags change)."""
    return window.context.state_for(spec.instance_id, spec.kind, spec.params,
                                    FIGURES[spec.kind].make_state)


def _live(window, spec) -> np.ndarray:
    """The same figure drawn live (the cache off for these frames)."""
    window.cache.enabled = False
    window.cache.release()
    try:
        return _frames(window, spec, 3)
    finally:
        window.cache.enabled = True


def test_an_unchanged_figure_is_drawn_once_it_settles_then_shown_from_its_picture(window):
    spec = make_figure("clamped-cosine", normal_deg=30)
    cache = window.cache
    pixels = _frames(window, spec)
    name = spec.instance_id
    # live until its inputs were the same two frames in a row, then copied once
    assert cache.draws[name] == 2, dict(cache.draws)
    assert cache.shown[name] == FRAMES - 2
    assert len(cache.pictures) == 1
    assert window.ctx.error == "GL_NO_ERROR"
    live = _live(window, spec)
    assert pixels.shape == live.shape and np.array_equal(pixels, live)


def test_a_changed_input_draws_the_figure_again(window):
    spec = make_figure("clamped-cosine", normal_deg=30)
    cache = window.cache
    before = _frames(window, spec)
    state = _state(window, spec)
    drawn = cache.draws[spec.instance_id]
    state.normal_deg = 75.0                   # the reader dragged the normal
    after = _frames(window, spec)
    assert cache.draws[spec.instance_id] == drawn + 2
    assert not np.array_equal(before, after)
    assert np.array_equal(after, _live(window, spec))
    other = make_figure("clamped-cosine", normal_deg=60)      # another parameter
    drawn = cache.draws[other.instance_id]
    _frames(window, other)
    assert cache.draws[other.instance_id] == drawn + 2


def test_a_hovered_figure_is_drawn_live_and_copied_again_after(window):
    from imgui_bundle import imgui

    spec = make_figure("clamped-cosine", normal_deg=30)
    cache = window.cache
    _frames(window, spec)
    (x0, y0), (x1, y1) = window.rect
    drawn = cache.draws[spec.instance_id]
    imgui.get_io().add_mouse_pos_event((x0 + x1) / 2, (y0 + y1) / 2)
    _frames(window, spec, 4)
    assert cache.draws[spec.instance_id] == drawn + 4     # every hovered frame
    assert spec.instance_id not in cache.pictures
    imgui.get_io().add_mouse_pos_event(-100.0, -100.0)
    _frames(window, spec, 4)
    assert spec.instance_id in cache.pictures             # copied again once settled


def test_a_playing_figure_is_never_shown_from_a_picture(window):
    spec = make_figure("propagation-stepper")
    cache = window.cache
    _frames(window, spec, 2)
    state = _state(window, spec)
    state.playing = True
    drawn = cache.draws[spec.instance_id]
    _frames(window, spec)
    assert cache.draws[spec.instance_id] == drawn + FRAMES
    assert spec.instance_id not in cache.pictures


def test_a_new_page_releases_the_pictures(window):
    spec = make_figure("cell-faces")
    cache = window.cache
    _frames(window, spec)
    texture = cache.pictures[spec.instance_id].texture
    window.page = object()                    # another lesson step
    drawn = cache.draws[spec.instance_id]
    _frames(window, spec, 1)
    assert isinstance(texture.mglo, moderngl.InvalidObject)
    assert cache.draws[spec.instance_id] == drawn + 1


def test_a_figure_of_the_frames_is_drawn_again_for_new_results(window):
    from figure_cases import synthetic_result

    spec = make_figure("flux-per-step")
    cache = window.cache
    window.context.results = (synthetic_result("corrected"),)
    _frames(window, spec)
    drawn = cache.draws[spec.instance_id]
    assert spec.instance_id in cache.pictures
    window.context.results = (synthetic_result("original"),)      # a new frame
    _frames(window, spec)
    assert cache.draws[spec.instance_id] == drawn + 2


def test_a_cached_figure_keeps_no_frame_result_alive(window):
    import gc
    import types
    import weakref

    from figure_cases import synthetic_result

    class Result(types.SimpleNamespace):       # weakly referable, as FrameResult is
        pass

    spec = make_figure("flux-per-step")
    cache = window.cache
    window.context.results = (Result(**vars(synthetic_result("corrected"))),)
    _frames(window, spec)
    assert spec.instance_id in cache.pictures
    gone = weakref.ref(window.context.results[0])
    window.context.results = ()       # the view moved on: only the cache could hold it
    gc.collect()
    assert gone() is None
