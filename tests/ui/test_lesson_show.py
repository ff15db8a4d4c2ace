"""A lesson step's in-scene overlays (``[steps.show]``): every shipped table validates
against OverlayState's specs and the step's settings, a bad one is refused with file, step
and field named, applying a step sets its overlays and leaving gives the reader's back."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from explorer.lessons import LessonError, load_all, load_lesson
from explorer.lpv.settings import Settings
from explorer.overlay_params import READER_FIELDS, OverlayState, check_show
from explorer.schema import specs


@pytest.fixture(scope="module")
def shipped():
    lessons, errors = load_all()
    assert errors == [], "\n".join(str(e) for e in errors)
    return lessons


def test_every_show_table_validates(shipped):
    shown = 0
    for lesson in shipped:
        for step in lesson.steps:
            where = f"{lesson.id} step {step.number}"
            fields = dict(step.show)
            assert set(fields) <= set(specs(OverlayState)) - set(READER_FIELDS), where
            assert check_show(fields, step.settings()) == fields, where
            overlays = step.overlays()
            assert all(getattr(overlays, name) == value for name, value in fields.items())
            shown += bool(fields)
    assert shown >= 20


def test_no_single_source_step_leaves_the_patch_alone_in_the_void(shipped):
    """The single-source scene is one lit patch in an empty box: a step of it must draw
    the grid's light in the scene, and say so in its caption."""
    from explorer.ui.lesson_panel import step_caption

    steps = [(lesson.id, step) for lesson in shipped for step in lesson.steps
             if step.scene == "single-source"]
    assert len(steps) >= 10
    for lesson_id, step in steps:
        overlays = step.overlays()
        assert overlays.slice or overlays.glyphs, f"{lesson_id} step {step.number}"
        assert step_caption(step).startswith("Look at the main view ("), lesson_id
        assert "Inspect" not in step.text, f"{lesson_id} step {step.number}"


GOOD = '''
id = "shown"
title = "Shown"
summary = "A step that draws in the scene."
scene = "single-source"
[[steps]]
title = "In flight"
text = "Look."
[steps.settings]
iterations = 4
[steps.show]
slice = true
slice_quantity = "in-flight"
slice_step = 2
glyphs = true
'''


def _load(tmp_path: Path, text: str):
    path = tmp_path / "60-shown.toml"
    path.write_text(text, encoding="utf-8")
    return load_lesson(path, check_formula=None)


def _refused(tmp_path: Path, old: str, new: str) -> LessonError:
    with pytest.raises(LessonError) as info:
        _load(tmp_path, GOOD.replace(old, new))
    error = info.value
    assert "60-shown.toml" in str(error) and "step 1 ('In flight')" in str(error)
    assert error.step == 1
    return error


def test_a_show_table_loads_in_file_order(tmp_path):
    step = _load(tmp_path, GOOD).step(1)
    assert step.show == (("slice", True), ("slice_quantity", "in-flight"),
                         ("slice_step", 2), ("glyphs", True))
    overlays = step.overlays()
    assert overlays.slice and overlays.glyphs and overlays.slice_step == 2
    assert not overlays.vpls and overlays.picked_kind == "none"     # nothing else


@pytest.mark.parametrize("old, new, field, words", [
    ("glyphs = true", "glyhps = true", "show.glyhps", "unknown field"),
    ("glyphs = true", 'slice_axis = "w"', "show.slice_axis", "one of 'x', 'y', 'z'"),
    ("glyphs = true", "slice_opacity = 2", "show.slice_opacity", "in [0, 1], got 2"),
    ("slice = true", 'slice = "yes"', "show.slice", "true or false"),
    ("slice_step = 2", "slice_step = 5", "show.slice_step", "past the last propagation step"),
    ("glyphs = true", "fly = true", "show.fly", "reader's own control"),
    ("glyphs = true", 'glyphs = true\nglyph_cells = "picked"', "show.glyph_cells",
     "picked point"),
    ("glyphs = true", "blockers = true", "show.blockers", "geometry volume"),
    ('slice_quantity = "in-flight"', 'slice_quantity = "sh5"', "show.slice_quantity",
     "sh_order 2"),
    ("glyphs = true", "cascade = 2", "show.cascade", "1 cascade"),
])
def test_a_bad_show_table_names_file_step_and_field(tmp_path, old, new, field, words):
    error = _refused(tmp_path, old, new)
    assert error.field == field and words in str(error), str(error)


def test_show_must_be_a_table(tmp_path):
    text = GOOD.split("[steps.show]")[0].replace('text = "Look."', 'text = "Look."\nshow = 3')
    with pytest.raises(LessonError) as info:
        _load(tmp_path, text)
    assert info.value.field == "show" and "must be a table" in str(info.value)


def test_a_picked_cell_with_glyphs_around_it_is_allowed(tmp_path):
    step = _load(tmp_path, GOOD.replace("glyphs = true", 'glyphs = true\nglyph_cells = '
                                        '"picked"\npicked_kind = "cell"\npicked_wy = -0.35'))
    assert step.step(1).overlays().picked_point == (0.0, -0.35, 0.0)


def test_applying_a_step_sets_its_overlays_and_leaving_restores_them(shipped):
    from explorer.ui.lesson_panel import LessonSession, Screen, current_screen, show_screen
    from explorer.ui.state import AppState

    state = AppState(settings=Settings(width=320, height=240),
                     overlays=OverlayState(vpls=True, lattice=True, fly=True))
    state.inspect.source = "rsm-flux"
    state.overlays.pick("cell", "A", 0, (0.1, 0.2, 0.3))
    reader = replace(state.overlays)
    session = LessonSession(lessons=shipped)
    lesson = session.open("solid-angles")
    first = lesson.step(1)
    show_screen(state, session.apply(current_screen(state)))
    # the step's overlays, nothing of the reader's view but the fly mode
    assert state.overlays == first.overlays(reader)
    assert state.overlays.slice and state.overlays.slice_quantity == "in-flight"
    assert not state.overlays.vpls and state.overlays.picked_kind == "none"
    assert state.overlays.fly
    assert state.requests.focus_panel == ("Show in scene",)
    assert isinstance(session.saved, Screen) and session.saved.overlays == reader
    # the reader adds an overlay: it survives a try-this and its undo, not a new step
    state.overlays.vpls = True
    show_screen(state, session.toggle_try(1, current_screen(state)))
    assert state.overlays.vpls and state.overlays.slice
    show_screen(state, session.toggle_try(1, current_screen(state)))
    assert state.overlays.vpls and session.tried is None
    assert session.next()
    show_screen(state, session.apply(current_screen(state)))
    assert state.overlays == lesson.step(2).overlays(reader) and not state.overlays.vpls
    # editing the overlays on screen never reaches the saved copy
    state.overlays.blockers = True
    assert session.saved.overlays == reader
    show_screen(state, session.leave())
    assert state.overlays == reader and state.overlays.picked_point == (0.1, 0.2, 0.3)
