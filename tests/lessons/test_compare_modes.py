"""A try-this's comparison mode (``compare``): read and refused with one line naming the
field, turned into the screen the window shows, rendered headlessly in each mode, and
every side shown at one shared colour scale that leaves the step's features readable
(or the caption says why not)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from explorer.lessons import LessonError, load_all, load_lesson, preview_settings
from explorer.lessons.compare_views import (
    exposure_note,
    grid_shape,
    render_try,
    white_at,
    white_share,
)
from explorer.lpv.settings import PRESETS, Settings

LESSON = '''
id = "compared"
title = "Compared"
summary = "A step whose try-this compares."
scene = "cornell"
[[steps]]
title = "Grid"
text = "Look."
[steps.settings]
iterations = 3
grid_size = 12
[[steps.try_this]]
control = "grid_size"
prompt = "Look."
compare = "difference"
value = 8
'''


def _load(tmp_path: Path, text: str):
    path = tmp_path / "60-compared.toml"
    path.write_text(text, encoding="utf-8")
    return load_lesson(path, check_formula=None)


def _refused(tmp_path: Path, old: str, new: str) -> LessonError:
    assert old in LESSON
    with pytest.raises(LessonError) as info:
        _load(tmp_path, LESSON.replace(old, new))
    return info.value


def test_each_mode_loads_and_split_true_is_split(tmp_path):
    for mode in ("split", "difference", "side-by-side"):
        item = _load(tmp_path, LESSON.replace('"difference"', f'"{mode}"')).steps[0].try_this[0]
        assert item.compare == mode and item.compares and item.variants == (8,)
    old = _load(tmp_path, LESSON.replace('compare = "difference"', "split = true"))
    assert old.steps[0].try_this[0].compare == "split" and old.steps[0].try_this[0].split
    plain = _load(tmp_path, LESSON.replace('compare = "difference"\n', ""))
    assert plain.steps[0].try_this[0].compare == "apply"
    assert not plain.steps[0].try_this[0].compares
    many = _load(tmp_path, LESSON.replace('compare = "difference"\nvalue = 8',
                                          'compare = "small-multiples"\nvalues = [8, 16, 4]'))
    item = many.steps[0].try_this[0]
    assert item.variants == (8, 16, 4) and item.value == 8


@pytest.mark.parametrize("old, new, field, words", [
    ('"difference"', '"sideways"', "try_this[0].compare", "must be one of"),
    ('compare = "difference"', 'compare = "split"\nsplit = true', "try_this[0].split",
     "give compare alone"),
    ("value = 8", "values = [8, 16]", "try_this[0].values", "small-multiples"),
    ('compare = "difference"\nvalue = 8', 'compare = "small-multiples"\nvalue = 8',
     "try_this[0].values", "several values"),
    ('compare = "difference"\nvalue = 8', 'compare = "small-multiples"\nvalues = [8, 4, 6, 10]',
     "try_this[0].values", "2 to 3"),
    ('compare = "difference"\nvalue = 8', 'compare = "small-multiples"\nvalues = [8, 8]',
     "try_this[0].values[1]", "shown twice"),
    ('compare = "difference"\nvalue = 8', 'compare = "small-multiples"\nvalues = [8, 12]',
     "try_this[0].values[1]", "change nothing"),
    ('compare = "difference"\nvalue = 8', 'compare = "small-multiples"\nvalues = [8, 16]'
     "\nvalue = 8", "try_this[0].value", "values alone"),
    ('value = 8', 'value = 8\ncamera = { eye = [0, 1, 3], target = [0, 1, 0] }',
     "try_this[0].camera", "difference try-this"),
])
def test_a_bad_comparison_is_one_line_naming_the_field(tmp_path, old, new, field, words):
    error = _refused(tmp_path, old, new)
    assert error.field == field and words in error.reason, str(error)
    assert "\n" not in str(error) and "step 1" in str(error)


def test_each_mode_is_the_screen_the_window_shows(tmp_path):
    from explorer.ui.lesson_panel import Screen, step_screen, try_screen

    own = Screen(settings=Settings(), compare_settings=Settings(corrections=PRESETS["original"]),
                 view_mode="single")
    for mode in ("split", "difference", "side-by-side"):
        step = _load(tmp_path, LESSON.replace('"difference"', f'"{mode}"')).steps[0]
        shown = try_screen(step, 1, own)
        assert shown.view_mode == mode and shown.settings == step_screen(step, own).settings
        assert dict(shown.compare_overrides) == {"grid_size": 8} and not shown.compare_variants
    step = _load(tmp_path, LESSON.replace('compare = "difference"\nvalue = 8',
                                          'compare = "small-multiples"\nvalues = [8, 16, 4]'
                                          )).steps[0]
    shown = try_screen(step, 1, own)
    assert shown.view_mode == "small-multiples" and dict(shown.compare_overrides) == {
        "grid_size": 8}
    assert [dict(v) for v in shown.compare_variants] == [{"grid_size": 16}, {"grid_size": 4}]


def test_grid_shape_fills_the_area():
    assert grid_shape(2, 1600, 600) == (2, 1)
    assert grid_shape(4, 800, 600) == (2, 2)
    assert grid_shape(3, 1800, 400) == (3, 1)
    assert grid_shape(3, 400, 1200) == (1, 3)


def test_render_try_composes_each_mode(ctx, tmp_path):
    from explorer.lpv.pipeline import Pipeline

    pictures = {}
    with Pipeline(Settings(width=32, height=32), ctx=ctx) as pipeline:
        for mode, change in (("split", "value = 8"), ("difference", "value = 8"),
                             ("side-by-side", "value = 8"),
                             ("small-multiples", "values = [8, 16, 4]")):
            text = LESSON.replace('"difference"', f'"{mode}"').replace("value = 8", change)
            step = _load(tmp_path, text).steps[0]
            pictures[mode] = render_try(pipeline, step, 1, preview_settings(step, size=32))
    split, diff = pictures["split"], pictures["difference"]
    assert split.image.shape == (32, 32, 3)
    np.testing.assert_array_equal(split.image[:, :16], split.sides[0][:, :16])
    np.testing.assert_array_equal(split.image[:, 17:], split.sides[1][:, 17:])
    assert diff.image.shape == (32, 32, 3) and diff.image.max() == pytest.approx(1.0)
    pair = pictures["side-by-side"]
    assert pair.image.shape == (32, 66, 3)
    np.testing.assert_array_equal(pair.image[:, 34:], pair.sides[1])
    grid = pictures["small-multiples"]
    assert grid.image.shape == (66, 66, 3) and len(grid.sides) == 4
    np.testing.assert_array_equal(grid.image[34:, :32], grid.sides[2])
    np.testing.assert_array_equal(grid.image[34:, 34:], grid.sides[3])
    np.testing.assert_array_equal(grid.image[32:34], 0.0)           # the gap
    assert not np.array_equal(grid.sides[1], grid.sides[3])         # grid 8 against grid 4


def test_every_side_is_shown_at_the_steps_display_scale(ctx, tmp_path):
    """With the auto exposure on, B (another grid: other brightness) is shown at A's
    display scale, not at its own."""
    from explorer.lpv.pipeline import Pipeline

    step = _load(tmp_path, LESSON.replace("grid_size = 12", "grid_size = 12\n"
                                          "auto_exposure = true")
                 ).steps[0]
    settings = preview_settings(step, size=32).with_changes(auto_exposure=True)
    with Pipeline(settings, ctx=ctx) as pipeline:
        picture = render_try(pipeline, step, 1, settings)
        a_scale = float(picture.results[0].display_scale)
        own_b = float(picture.results[1].display_scale)
        b_own_view = pipeline.view("final")         # B's last frame at its own scale
    assert picture.display_scale == a_scale and own_b != pytest.approx(a_scale, rel=1e-3)
    assert not np.allclose(picture.sides[1], b_own_view)


def test_exposure_note_says_why_a_side_is_white():
    white = np.full((4, 4, 3), 100.0, np.float32)
    dark = np.full((4, 4, 3), 0.01, np.float32)
    assert white_share(white, 1.0) == 1.0 and white_share(dark, 1.0) == 0.0
    assert exposure_note("B", 0.0) == ""
    assert exposure_note("B", 0.66).startswith("B: 66% white at A's exposure")
    shown = np.zeros((8, 8, 3))
    shown[:3, :3] = 1.0
    assert white_at(shown, [(1.0, 1.0), (6.0, 6.0)]) == [True, False]


KNOWN_WHITE = {"11/3 try 1": "in-place propagation runs away: the text says B blows up"}
"""Comparing try-this whose changed side the shared exposure shows white, and why; the
window's caption says so (``exposure_note``)."""


def test_the_shared_scale_leaves_every_named_feature_readable(ctx):
    """Every comparing try-this of the course, each side at the step's exposure and
    display scale: no side reads white over more than MOST_WHITE of its pixels (unless
    listed in KNOWN_WHITE, whose caption says why), and no labelled mark's point is
    white on any side."""
    from explorer.lpv.pipeline import Pipeline
    from explorer.ui.overlays.marks import placements

    lessons, errors = load_all(check_formula=None)
    assert not errors
    cases = [(lesson, step, index) for lesson in lessons for step in lesson.steps
             for index, item in enumerate(step.try_this, 1) if item.compares]
    assert len(cases) >= 20
    white, marks_white = {}, []
    with Pipeline(preview_settings(cases[0][1]), ctx=ctx) as pipeline:
        for lesson, step, index in cases:
            where = f"{lesson.number:02d}/{step.number} try {index}"
            picture = render_try(pipeline, step, index, preview_settings(step, size=64))
            notes = [exposure_note(chr(ord("A") + n), white_share(result.final_image,
                                                                  picture.display_scale))
                     for n, result in enumerate(picture.results)]
            if any(notes):
                white[where] = notes
            labelled = [mark for mark in step.marks if mark.label]
            if labelled:
                placed = placements(picture.results[0], labelled, (0.0, 0.0), (64.0, 64.0),
                                    lambda label: (7.0 * len(label), 15.0))
                points = [p.point for p in placed if p.visible]
                for n, side in enumerate(picture.sides):
                    if any(white_at(side, points)):
                        marks_white.append(f"{where} side {n}")
    assert set(white) == set(KNOWN_WHITE), white
    assert not marks_white, marks_white


def test_the_windows_caption_says_when_the_shared_scale_whitens_a_side():
    """The View panel's label of a side (``panels.view.washed_out``): a side shown white
    at A's exposure says so; exposed on its own (split, Expose sides separately) it
    needs no note, but in small multiples every view shares A's scale."""
    from types import SimpleNamespace

    from explorer.ui.panels.view import washed_out
    from explorer.ui.picture import SideDisplay
    from explorer.ui.state import AppState

    state = AppState(view_mode="split")
    bright = np.full((8, 8, 3), 50.0, np.float32)
    rt = state.runtime
    rt.frame.pictures = {"B": SimpleNamespace(result=SimpleNamespace(
        final_image=bright, indirect=bright * 0.0))}
    rt.frame.displays = {"B": SideDisplay(1.0, 1.0, "filmic", False)}
    assert washed_out(state, "B").startswith("B: 100% white at A's exposure")
    rt.frame.displays = {"B": SideDisplay(1.0, 1.0, "filmic", True)}    # indirect only
    assert washed_out(state, "B") == ""
    rt.frame.displays = {"B": SideDisplay(1.0, 1.0, "filmic", False)}
    state.expose_sides_separately = True
    assert washed_out(state, "B") == ""
    state.view_mode = "small-multiples"
    assert washed_out(state, "B") != ""
