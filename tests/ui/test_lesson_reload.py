"""A lesson of one's own edited while a real window (under Xvfb) shows it
(explorer/ui/lesson_watch.py): each save is read again and shown at the same step, with
its settings applied; a broken save keeps the last good lesson on screen and says why in
one line naming the file, the line and the key. The lesson is the one ``lessons new``
writes, in a folder listed beside the shipped course."""

from __future__ import annotations

import pytest
from window_cases import display_problem, run_child

_PROBLEM = display_problem()
pytestmark = pytest.mark.skipif(_PROBLEM is not None, reason=str(_PROBLEM))

_SCRIPT = r"""
import os, sys
from pathlib import Path
from explorer.cli import main
from explorer.lpv.settings import Settings
from explorer.ui.app import App
from explorer.ui.lesson_list import list_sections
from explorer.ui.state import AppState
from explorer.ui.window_options import WindowOptions

folder = Path(sys.argv[1])
assert main(["lessons", "new", "Mine", "--dir", str(folder)]) == 0
path = folder / "01-mine.toml"

def save(text):
    path.write_text(text, encoding="utf-8")
    stamp = path.stat().st_mtime_ns + 10_000_000      # a later save, whatever the clock
    os.utime(path, ns=(stamp, stamp))

def poll():
    app.controller.poll_shaders(state)
    for _ in range(2):
        assert app.frame()

state = AppState(settings=Settings(rsm_size=32, width=64, height=48), lesson_id="mine",
                 lesson_step=2, lesson_folder=str(folder))
app = App(state, WindowOptions(width=1280, height=720, visible=False, vsync=False,
                               persist_settings=False))
try:
    for _ in range(3):
        assert app.frame()
    session = state.lesson_session
    titles = [title for title, _ in list_sections(session.course())]
    assert titles == ["Your lessons (" + folder.name + ")", "The course"], titles
    assert len(session.lessons) > 1 and session.course().own(session.lesson)
    assert session.lesson.id == "mine" and session.step_number == 2 and session.applied
    assert state.view_buffer == "indirect" and state.settings.iterations == 16
    poll()                                   # the first poll starts watching the file
    text = path.read_text(encoding="utf-8")

    # a good edit: the step's title and view, and a setting of the lesson
    edited = text.replace('title = "One cell per step"', 'title = "Cell by cell"')
    edited = edited.replace('view = "indirect"', 'view = "direct"')
    edited = edited.replace("grid_size = 16", "grid_size = 12")
    save(edited)
    poll()
    assert session.step_number == 2 and session.step.title == "Cell by cell"
    assert state.view_buffer == "direct" and state.settings.grid_size == 12
    said = [m.text for m in state.messages]
    assert any("01-mine.toml changed on disk: reloaded at step 2" in t for t in said), said
    assert app.settle() is not None
    assert state.runtime.frame.result.settings.grid_size == 12

    # a broken edit: the last good lesson stays, one line says file, line and key
    broken = edited.replace("value = 2\n", "value = \"two\"\n")
    line = broken.splitlines().index("value = \"two\"") + 1
    save(broken)
    poll()
    errors = [m.text for m in state.messages if m.level == "error"]
    assert len(errors) == 1 and "\n" not in errors[0], errors
    assert f"01-mine.toml:{line}, step 2" in errors[0], errors[0]
    assert "field 'try_this[0].value'" in errors[0], errors[0]
    assert session.step.title == "Cell by cell" and state.settings.grid_size == 12
    assert session.reload_error and session.reload_error in errors[0]   # above the article
    for _ in range(3):
        assert app.frame()                   # the article still draws the good lesson

    # every other kind of slip: TOML syntax, a key the format lacks, a live value's name
    slips = [(edited.replace('view = "direct"', 'view = "direct'), 'view = "direct',
              "TOML syntax error"),
             (edited.replace('view = "direct"', 'view = "direct"\ncolour = "red"'),
              'colour = "red"', "step 2 ('Cell by cell'), field 'colour': unknown field"),
             (edited.replace("{{frame.cell_size:.3f}}", "{{frame.cellsize:.3f}}"),
              "{{frame.cellsize:.3f}} m cells here. The view shows the indirect light alone.",
              "field 'text': {{frame.cellsize}}: no live quantity 'frame.cellsize'; did you "
              "mean frame.cell_size")]
    for slip, where, says in slips:
        before = len(errors)
        save(slip)
        poll()
        errors = [m.text for m in state.messages if m.level == "error"]
        assert len(errors) == before + 1 and "\n" not in errors[-1], errors
        line = slip.splitlines().index(where) + 1
        assert f"01-mine.toml:{line}" in errors[-1] and says in errors[-1], errors[-1]
        assert session.step_number == 2 and session.step.title == "Cell by cell"
        assert state.view_buffer == "direct" and state.settings.grid_size == 12
        assert session.reload_error in errors[-1]
        for _ in range(2):
            assert app.frame()
    if len(sys.argv) > 2:                    # a look at the window with the last slip
        app.screenshot(sys.argv[2])

    # the next good save is shown again
    save(edited.replace('title = "Cell by cell"', 'title = "Cells"'))
    poll()
    assert session.step.title == "Cells" and session.step_number == 2
    assert session.reload_error is None

    # back at the list, a lesson added to the folder is listed
    from explorer.ui.lesson_panel import show_screen
    show_screen(state, session.close())
    state.lesson_id = None
    poll()
    assert main(["lessons", "new", "Second", "--dir", str(folder)]) == 0
    poll()
    assert "second" in [lesson.id for lesson in session.lessons]
    assert any(m.text.endswith(": lessons read again") for m in state.messages)
finally:
    app.close()
print("reload ok")
"""


def test_a_saved_lesson_reloads_at_its_step_and_a_broken_one_keeps_the_last(tmp_path):
    proc = run_child(["-c", _SCRIPT, str(tmp_path / "mine")], tmp_path)
    assert proc.returncode == 0 and "reload ok" in proc.stdout, proc.stdout + proc.stderr


def test_run_opens_a_lesson_of_the_folder(tmp_path):
    """``run --lessons DIR --lesson ID --step K``: the folder's lesson, in the window."""
    from explorer.cli import main

    folder = tmp_path / "mine"
    assert main(["lessons", "new", "Mine", "--dir", str(folder)]) == 0
    shot = tmp_path / "run.png"
    proc = run_child(["-m", "explorer", "run", "--lessons", str(folder), "--lesson", "mine",
                      "--step", "2", "--hidden", "--no-persist", "--size", "1280x720",
                      "--screenshot", str(shot), "--frames", "4"], tmp_path)
    assert proc.returncode == 0 and shot.is_file(), proc.stdout + proc.stderr
    proc = run_child(["-m", "explorer", "run", "--lessons", str(folder), "--no-shipped",
                      "--lesson", "overview", "--hidden"], tmp_path)
    assert proc.returncode == 2 and "no lesson 'overview'" in proc.stderr, proc.stderr
