"""The window opens at a size that fits the monitor's work area and remembers the size
the user gave it."""

from __future__ import annotations

import pytest
from window_cases import display_problem, run_child

from explorer.ui.state import MIN_WINDOW_SIZE, WINDOW_FRAME_PX, fit_work_area


def test_a_window_larger_than_the_work_area_shrinks_to_fit_it_centred():
    size, position = fit_work_area((1600, 960), (0, 0, 1280, 800))
    assert size == (1280 - WINDOW_FRAME_PX[0], 800 - WINDOW_FRAME_PX[1])
    # frame included, the window lies inside the work area
    left, top = position
    assert left - WINDOW_FRAME_PX[0] // 2 >= 0 and left + size[0] <= 1280
    assert top - (WINDOW_FRAME_PX[1] - WINDOW_FRAME_PX[0] // 2) >= 0
    assert top + size[1] + WINDOW_FRAME_PX[0] // 2 <= 800


def test_a_window_that_fits_keeps_its_size_and_is_centred_on_a_second_monitor():
    size, (left, top) = fit_work_area((1000, 700), (1920, 30, 1600, 1000))
    assert size == (1000, 700)
    assert 1920 < left and left + size[0] < 1920 + 1600
    assert abs((left - 1920) - (1920 + 1600 - left - size[0])) <= WINDOW_FRAME_PX[0]
    assert 30 < top and top + size[1] < 1030


def test_no_work_area_keeps_the_size_and_a_tiny_area_keeps_the_smallest_window():
    assert fit_work_area((1600, 960), None) == ((1600, 960), None)
    size, _ = fit_work_area((1600, 960), (0, 0, 100, 80))
    assert size == (MIN_WINDOW_SIZE, MIN_WINDOW_SIZE)


_SCRIPT = r"""
import json, sys
from explorer.gl.window import work_area
from explorer.ui.app import App
from explorer.ui.window_options import WindowOptions
from explorer.ui.state import AppState, fit_work_area

area = work_area()
x, y, width, height = area
# a size saved on a larger screen: the window opens fitting this one
state = AppState(window_size=(width + 400, height + 300))
app = App(state, WindowOptions(persist_settings=False, pipeline_class=None))
opened = app.window.size
app.close()
# the user's own size, smaller than the screen, is what the window reopens at (saved)
app = App(None, WindowOptions(persist_settings=True, pipeline_class=None))
app.window.set_size(width // 2, height // 2)
for _ in range(3):
    app.frame()
app.close()
app = App(None, WindowOptions(persist_settings=True, pipeline_class=None))
again = app.window.size
app.close()
print(json.dumps({"area": area, "opened": opened, "again": again,
                  "wanted": fit_work_area((width + 400, height + 300), area)[0]}))
"""


@pytest.mark.skipif(display_problem() is not None, reason=str(display_problem()))
def test_the_window_opens_within_the_work_area_and_reopens_at_the_users_size(tmp_path):
    import json

    done = run_child(["-c", _SCRIPT], tmp_path, timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    report = json.loads(done.stdout.strip().splitlines()[-1])
    x, y, width, height = report["area"]
    assert tuple(report["opened"]) == tuple(report["wanted"])
    assert report["opened"][0] <= width and report["opened"][1] <= height
    assert tuple(report["again"]) == (width // 2, height // 2)


_BUFFERS_SCRIPT = r"""
import ctypes, json
from explorer.gl.window import Window
window = Window(320, 200, visible=False, vsync=False)
gl = ctypes.CDLL("libGL.so.1")
query = gl.glGetFramebufferAttachmentParameteriv
query.argtypes = [ctypes.c_uint, ctypes.c_uint, ctypes.c_uint, ctypes.POINTER(ctypes.c_int)]
GL_FRAMEBUFFER, GL_BACK_LEFT, GL_DEPTH, GL_STENCIL = 0x8D40, 0x0402, 0x1801, 0x1802
GL_OBJECT_TYPE = 0x8CD0        # GL_NONE (0) where the default framebuffer lacks it
sizes = {}
window.ctx.screen.use()
for name, attachment in (("colour", GL_BACK_LEFT), ("depth", GL_DEPTH),
                         ("stencil", GL_STENCIL)):
    value = ctypes.c_int(-1)
    query(GL_FRAMEBUFFER, attachment, GL_OBJECT_TYPE, ctypes.byref(value))
    sizes[name] = value.value
print(json.dumps(sizes))
window.close()
"""


@pytest.mark.skipif(display_problem() is not None, reason=str(display_problem()))
def test_the_window_has_no_depth_or_stencil_buffer(tmp_path):
    """Only imgui draws into the window (the view and its overlays draw into framebuffers
    of their own, with their own depth): a depth and stencil buffer there is cleared and
    swapped every frame for nothing (on llvmpipe at 1600×960 a clear and swap took 3.2–3.9
    ms of CPU with them, 0.5–0.7 without: BENCHMARKS.md)."""
    import json

    done = run_child(["-c", _BUFFERS_SCRIPT], tmp_path, timeout=120)
    assert done.returncode == 0, done.stderr[-3000:]
    sizes = json.loads(done.stdout.strip().splitlines()[-1])
    framebuffer_default, none = 0x8218, 0
    assert sizes == {"colour": framebuffer_default, "depth": none, "stencil": none}
