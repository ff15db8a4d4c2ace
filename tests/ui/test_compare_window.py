"""A try-this's comparison modes in a real window under Xvfb (a child process: a GLX
window cannot become current where the tests' EGL context was): split, difference,
side by side and small multiples drawn from a lesson of the test's own; the grid's
further view rendered and shown at A's exposure; the try-this's numbers before and after
the press both kept after Undo."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from window_cases import display_problem

ROOT = Path(__file__).resolve().parents[2]
_PROBLEM = display_problem()
pytestmark = pytest.mark.skipif(_PROBLEM is not None, reason=str(_PROBLEM))

LESSON = '''
id = "compared"
title = "Compared"
summary = "Every way a try-this compares."
scene = "cornell"
[[steps]]
title = "Four ways"
text = "Look at the indirect light."
view = "indirect"
[steps.settings]
grid_size = 8
iterations = 2
rsm_size = 32
[[steps.try_this]]
control = "iterations"
value = 6
compare = "side-by-side"
prompt = "Six steps: the surfaces gather {{audit.gathered:.4g}} W."
[[steps.try_this]]
control = "iterations"
values = [4, 8]
compare = "small-multiples"
prompt = "Two, four and eight steps."
[[steps.try_this]]
control = "corrections.propagation_4pi"
value = false
compare = "difference"
prompt = "The published propagation: what changed."
[[steps.try_this]]
control = "grid_size"
value = 16
compare = "split"
prompt = "Sixteen cells on the right."
'''

_SCRIPT = r"""
import sys

import numpy as np
from explorer.lessons import live_values
from explorer.ui.app import App
from explorer.ui.lesson_panel import current_screen, show_screen
from explorer.ui.state import AppState
from explorer.ui.window_options import WindowOptions

state = AppState(lesson_folder=sys.argv[1], lesson_folder_alone=True, lesson_id="compared",
                 lesson_step=1)
app = App(state, WindowOptions(width=960, height=600, visible=False, vsync=False,
                               persist_settings=False))


def press(index):
    show_screen(state, session.toggle_try(index, current_screen(state)))
    assert app.settle() is not None
    app.frame(capture=True)
    x0, y0, x1, y1 = (int(round(v)) for v in state.runtime.view.view_rect)
    return app.last_pixels[y0:y1, x0:x1, :3].astype(np.float64)


def lit(image):
    return float((image.max(axis=2) > 30).mean())


try:
    for _ in range(3):
        assert app.frame()
    assert app.settle() is not None
    session = state.lesson_session
    step = session.step
    assert session.applied and step.title == "Four ways"
    rt = state.runtime
    app.frame()
    before_gathered = live_values.render("audit.gathered", ".4g",
                                         live_values.LiveContext(state.settings, rt.frame.result))

    # side by side: A and B whole, one row, each rendered at the cell's size
    view = press(1)
    assert state.view_mode == "side-by-side", state.view_mode
    height, width = view.shape[:2]
    assert rt.view.view_size[0] * 2 <= width * 1.01 + 8, (rt.view.view_size, width)
    left, right = view[:, : width // 2 - 4], view[:, width // 2 + 4:]
    assert lit(left) > 0.05 and lit(right) > 0.05, (lit(left), lit(right))
    assert np.abs(left - right[:, : left.shape[1]]).mean() > 1.0    # 2 against 6 steps
    assert rt.frame.compare_result.settings.iterations == 6
    app.frame()                  # the article keeps the press's frame
    show_screen(state, session.toggle_try(1, current_screen(state)))       # Undo
    assert app.settle() is not None
    app.frame()
    assert state.view_mode == "single"
    frames, key = session.try_frames, ("compared", 1, 1)
    after = live_values.LiveContext(step.try_this[0].apply(state.settings), None)
    kept = frames.after_context(key, after)
    after_gathered = live_values.render("audit.gathered", ".4g", kept)
    note = frames.before_note(("compared", 1), step.try_this[0].prompt,
                              live_values.LiveContext(state.settings, rt.frame.result))
    assert after_gathered != before_gathered and live_values.PENDING not in after_gathered
    assert note == f"before the press: {before_gathered} W", (note, before_gathered)

    # small multiples: A, B and C, each its own pipeline, all at A's exposure
    state.expose_sides_separately = True
    view = press(2)
    assert state.view_mode == "small-multiples"
    assert app.controller.active_sides(state) == ("A", "B", "C")
    assert {"A", "B", "C"} <= set(rt.frame.pictures)
    assert rt.frame.pictures["C"].result.settings.iterations == 8
    assert rt.frame.compare_result.settings.iterations == 4
    display_a = rt.frame.displays["A"]
    for side in ("B", "C"):
        shown = rt.frame.displays[side]
        assert (shown.exposure, shown.scale) == (display_a.exposure, display_a.scale), side
    assert lit(view) > 0.1
    state.expose_sides_separately = False

    # difference: |A - B| in false colour beside its scale bar
    view = press(3)
    assert state.view_mode == "difference" and lit(view) > 0.02

    # split: A left of the divider, B right
    view = press(4)
    assert state.view_mode == "split"
    assert rt.frame.compare_result.settings.grid_size == 16
    show_screen(state, session.toggle_try(4, current_screen(state)))       # Undo
    app.frame()
    assert state.view_mode == "single" and state.compare_variants == ()
    assert [m.text for m in state.messages if m.level == "error"] == []
finally:
    app.close()
print("compare ok")
"""


def test_every_comparison_mode_in_the_window(tmp_path):
    folder = tmp_path / "lessons"
    folder.mkdir()
    (folder / "60-compared.toml").write_text(LESSON, encoding="utf-8")
    env = dict(os.environ, XDG_CONFIG_HOME=str(tmp_path / "config"),
               XDG_CACHE_HOME=str(tmp_path / "cache"))
    proc = subprocess.run([sys.executable, "-c", _SCRIPT, str(folder)], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0 and "compare ok" in proc.stdout, proc.stdout + proc.stderr
