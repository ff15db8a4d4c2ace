"""The Lesson panel in a real window under Xvfb (child processes: a GLX window cannot
become current in a process that made the tests' EGL context current): the article
column in its own dock, typeset text, a try-this button applied and undone, the
before | after split, leaving the lesson; ``run --lesson ID --step K`` and
``lessons --export``."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from window_cases import display_problem

ROOT = Path(__file__).resolve().parents[2]
_PROBLEM = display_problem()
pytestmark = pytest.mark.skipif(_PROBLEM is not None, reason=str(_PROBLEM))


def _run(args: list[str], tmp_path: Path, timeout: float = 600) -> subprocess.CompletedProcess:
    env = dict(os.environ, XDG_CONFIG_HOME=str(tmp_path / "config"),
               XDG_CACHE_HOME=str(tmp_path / "cache"))
    return subprocess.run([sys.executable, *args], cwd=ROOT, env=env, capture_output=True,
                          text=True, timeout=timeout)


_SCRIPT = r"""
import numpy as np
from imgui_bundle import imgui
from imgui_bundle.imgui import internal
from explorer.lpv.settings import Settings
from explorer.ui.app import App
from explorer.ui.window_options import WindowOptions
from explorer.ui.lesson_panel import current_screen, show_screen
from explorer.ui.state import AppState

own = Settings(grid_size=12, iterations=3, rsm_size=32, exposure=2.0)
state = AppState(settings=own, lesson_id="radiometry", lesson_step=4)
app = App(state, WindowOptions(width=1280, height=720, visible=False, vsync=False,
                               persist_settings=False))
try:
    for _ in range(3):
        assert app.frame()
    assert app.settle()
    session = state.lesson_session
    step = session.step
    assert session.lesson.id == "radiometry" and step.number == 4 and session.applied
    assert state.settings.grid_size == 16 and state.settings.exposure == 2.0
    assert state.runtime.frame.result is not None
    # the Lesson window is docked alone: no other window shares its dock node
    window = internal.find_window_by_name("Lesson")
    assert window is not None and window.dock_node is not None
    assert window.dock_node.windows.size() == 1, window.dock_node.windows.size()
    for other in ("View", "Corrections", "Inspect", "Error"):
        found = internal.find_window_by_name(other)   # the reader's mode hides unused ones
        assert found is None or found.dock_node is None or \
            found.dock_node.id_ != window.dock_node.id_
    assert internal.find_window_by_name("View").dock_node.id_ != window.dock_node.id_
    corrections = internal.find_window_by_name("Corrections")     # this step switches none
    assert corrections is None or not corrections.active
    assert window.size.x >= 400
    # the text was typeset: formulas cached without errors, fonts loaded
    rt = state.runtime
    assert rt.services.formulas.error is None, rt.services.formulas.error
    assert rt.services.fonts is not None
    assert {"regular", "bold", "italic", "code"} <= set(rt.services.fonts.by_style)
    before = app.last_pixels
    app.frame(capture=True)
    column = app.last_pixels[40:700, 10:int(window.size.x) - 10]
    assert column.std() > 20                 # text, not an empty panel
    # a try-this with a split: A keeps the step, B (the pipeline's other side) the change
    index = next(i for i, t in enumerate(step.try_this, 1) if t.split)
    item = step.try_this[index - 1]
    show_screen(state, session.toggle_try(index, current_screen(state)))
    app.settle()
    assert state.view_mode == "split" and state.settings.grid_size == 16
    assert app.settings_for("B").grid_size == item.value
    assert rt.frame.compare_result is not None
    assert rt.frame.compare_result.settings.grid_size == item.value
    show_screen(state, session.toggle_try(index, current_screen(state)))   # undo
    app.frame()
    assert state.view_mode == "single" and state.compare_overrides == ()
    # leaving gives the reader's settings back
    show_screen(state, session.leave())
    app.frame()
    # the render size follows the View panel (explorer/ui/view_size.py), not the reader
    assert state.settings.with_changes(width=own.width, height=own.height) == own
    assert [m.text for m in state.messages if m.level == "error"] == []
finally:
    app.close()
print("article ok")
"""


def test_the_article_in_the_window(tmp_path):
    proc = _run(["-c", _SCRIPT], tmp_path)
    assert proc.returncode == 0 and "article ok" in proc.stdout, proc.stdout + proc.stderr


def test_run_opens_a_lesson_at_a_step_and_refuses_bad_ones(tmp_path):
    out = tmp_path / "step.png"
    proc = _run(["-m", "explorer", "run", "--no-persist", "--hidden", "--lesson", "overview",
                 "--step", "3", "--size", "1280x720", "--screenshot", str(out),
                 "--frames", "8"], tmp_path)
    assert proc.returncode == 0, proc.stderr
    from PIL import Image

    image = np.asarray(Image.open(out))
    assert image.shape == (720, 1280, 3) and image.std() > 20
    proc = _run(["-m", "explorer", "run", "--no-persist", "--hidden", "--lesson", "overview",
                 "--step", "9"], tmp_path)
    assert proc.returncode == 2 and "steps 1..4" in proc.stderr
    proc = _run(["-m", "explorer", "run", "--no-persist", "--step", "2"], tmp_path)
    assert proc.returncode == 2 and "--step needs --lesson" in proc.stderr


def test_export_writes_a_lesson_step(tmp_path):
    out = tmp_path / "export.png"
    proc = _run(["-m", "explorer", "lessons", "--export", "solid-angles", "--step", "1",
                 "--out", str(out), "--size", "1280x720"], tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert f"wrote {out}" in proc.stdout
    from PIL import Image

    image = np.asarray(Image.open(out)).astype(int)
    assert image.shape == (720, 1280, 3)
    article = image[60:700, 10:440]
    assert article.std() > 20                       # the article column holds text
    # with a try-this pressed: a before | after split, the window's right half differs
    proc = _run(["-m", "explorer", "lessons", "--export", "radiometry", "--step", "4",
                 "--try", "1", "--out", str(out), "--size", "1280x720"], tmp_path)
    assert proc.returncode == 0, proc.stderr
    proc = _run(["-m", "explorer", "lessons", "--export", "radiometry", "--step", "4",
                 "--try", "7", "--out", str(out)], tmp_path)
    assert proc.returncode == 2 and "try-this 1..1" in proc.stderr
    proc = _run(["-m", "explorer", "lessons", "--export", "nope", "--out", str(out)], tmp_path)
    assert proc.returncode == 2 and "no lesson 'nope'" in proc.stderr
    proc = _run(["-m", "explorer", "lessons", "--export", "overview", "--out",
                 str(tmp_path / "x.jpg")], tmp_path)
    assert proc.returncode == 2 and ".png" in proc.stderr


_OVERLAY_SCRIPT = r"""
import sys
import numpy as np
from PIL import Image
from explorer.ui.export import export_step

out = sys.argv[1]
shown = export_step("solid-angles", 1, f"{out}/shown.png", 1280, 720)
bare = export_step("solid-angles", 1, f"{out}/bare.png", 1280, 720, overlays=False)
assert shown.view_rect == bare.view_rect and shown.view_rect is not None
x0, y0, x1, y1 = shown.view_rect
a = np.asarray(Image.open(shown.path)).astype(int)
b = np.asarray(Image.open(bare.path)).astype(int)
view_a, view_b = a[y0:y1, x0:x1], b[y0:y1, x0:x1]
differ = float((np.abs(view_a - view_b).sum(axis=2) > 30).mean())
lit_a = float((view_a.max(axis=2) > 40).mean())
lit_b = float((view_b.max(axis=2) > 40).mean())
print(f"overlays ok {differ:.3f} {lit_a:.3f} {lit_b:.3f}")
"""


def test_a_single_source_step_draws_in_the_void(tmp_path):
    """The exported step shows the grid's light in the main view; without its
    overlays the same step is a lit patch in a black void."""
    proc = _run(["-c", _OVERLAY_SCRIPT, str(tmp_path)], tmp_path)
    assert proc.returncode == 0 and "overlays ok" in proc.stdout, proc.stdout + proc.stderr
    differ, lit_shown, lit_bare = map(float, proc.stdout.split("overlays ok")[1].split())
    assert differ > 0.1                 # a tenth of the view changed
    assert lit_bare < 0.05              # the patch alone: nearly all of the view is black
    assert lit_shown > 3 * lit_bare     # the slice and its glyphs fill it
