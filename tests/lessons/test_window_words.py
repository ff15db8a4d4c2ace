"""What the window draws for a lesson is words, whole: every string the reader's mode draws
while each shipped step is on screen (labels, captions, legends, tooltips, hovers) holds
no internal identifier, nothing runs past its panel or its dock tab at 1280×720, the Error
panel's images are large enough to read and a click enlarges them, and after "Leave
lesson settings" the article says its numbers are the reader's own frame's.

The strings come from the drawing code itself: tests/reader_walk.py steps through every
lesson in a real window (a child process) with imgui's text calls recorded; the builders
of the captions (the slice's colour bar and hover, the Inspect panel's grid names) are also
called for every step without a window."""

from __future__ import annotations

import json
from types import SimpleNamespace

import numpy as np
import pytest
from window_cases import display_problem, run_child

from explorer.lessons import load_all
from explorer.lessons.words import for_reader, window_word_problems

OLD_WINDOW_TEXTS = [
    "grid_8: flux 2√π·c0 per cell [W]", "acc_N: flux 2√π·c0 per cell [W]",
    "acc_N of cascade 1: SH coefficient 3 [W/sr]", "grid_0, slice z = 6",
    "flux per cell (acc_N)", "Band-0 SH constant Y00 = 1/(2√π).",
    "lights that shine (Settings.lights)", "stages (explorer.lpv.stage_list.STAGES)",
    "error.relative_l2: ‖LPV − reference‖ / ‖reference‖",
    "corrections.injection_pi.original: VPL intensity as published",
    "or drop a mesh or scene file (.toml, docs/SCENES.md) onto the window",
    "the l1_min the figure lobe shows",
]
"""Strings the window drew before these rules (each must be caught)."""


def test_the_window_rule_catches_internal_names():
    for text in OLD_WINDOW_TEXTS:
        assert window_word_problems(text), text
    for text in ("light in flight after step 8: flux per cell [W]",
                 "accumulated light, cascade 1: SH coefficient 3 [W/sr]",
                 "the share k_s of the radiance, Φ_p, ω_y", "after step 4, layer z = 6"):
        assert not window_word_problems(text), (text, window_word_problems(text))
    assert for_reader('Inject it (docs/MODEL.md "Injection"): half (rsm.surfel_area).') == \
        "Inject it: half."


def _fake_result(cascades: int, steps: int):
    """What slice_field reads of a FrameResult: the recorded steps and the grids."""
    from explorer.lpv.grid import GridSpec

    grid = np.random.default_rng(1).random((3, 4, 4, 4, 9)).astype(np.float32)
    specs = [GridSpec((0.0, 0.0, 0.0), 0.25 * 2 ** k, 4) for k in range(cascades)]
    return SimpleNamespace(steps=[grid] * steps, grid_spec=specs[0], accumulated=grid,
                           cascade_accumulated=[grid] * cascades if cascades > 1 else [],
                           cascade_specs=specs if cascades > 1 else [])


def test_every_steps_slice_caption_and_hover_are_words():
    """The colour bar's caption under the view and the slice's hover both show
    SliceField.label: built here for every shipped step that draws the slice, and for
    every quantity with one and several cascades."""
    from dataclasses import replace

    from explorer.ui.overlays import quantities as Q
    from explorer.ui.state import SLICE_QUANTITIES

    lessons, _ = load_all()
    checked = 0
    for lesson in lessons:
        for step in lesson.steps:
            overlays = step.overlays()
            if not overlays.slice:
                continue
            settings = step.settings()
            result = _fake_result(settings.cascades, settings.iterations + 1)
            label = Q.slice_field(result, overlays).label
            assert not window_word_problems(label), (lesson.id, step.number, label)
            checked += 1
    assert checked >= 10
    for quantity in SLICE_QUANTITIES:
        for cascades in (1, 3):
            overlays = replace(step.overlays(), slice=True, slice_quantity=quantity,
                               slice_step=2, cascade=cascades - 1)
            label = Q.slice_field(_fake_result(cascades, 4), overlays).label
            assert not window_word_problems(label), label


def test_grid_names_are_words():
    from explorer.ui.overlays.quantities import grid_words

    names = [grid_words(step=t) for t in range(4)] + [
        grid_words(cascade=k, cascades=c) for c in (1, 3) for k in range(c)]
    assert len(set(names)) == len(names)
    assert not [name for name in names if window_word_problems(name)]


def test_every_steps_tooltips_are_words():
    """The hover of every live number a step quotes and the tooltip of each try-this
    button, as the article builds them."""
    from explorer.lessons import live_values
    from explorer.lessons import text as lesson_text
    from explorer.ui.article_try import try_label

    lessons, _ = load_all()
    found = []
    for lesson in lessons:
        for step in lesson.steps:
            texts = [step.text] + [item.prompt for item in step.try_this] + \
                [spec.caption for spec in step.figures]
            for text in texts:
                for name, _ in lesson_text.placeholders(text):
                    quantity = live_values.lookup(name, step.figure_ids, step.mark_ids)
                    found += [(lesson.id, name, p)
                              for p in window_word_problems(for_reader(quantity.doc))]
            for item in step.try_this:
                for text in try_label(item):
                    found += [(lesson.id, item.control, p) for p in window_word_problems(text)]
    assert not found, found


def test_the_error_panels_images_are_large_and_enlarge():
    """In the tool column of a 1280×720 window the images are at least IMAGE_MIN_PX wide
    (three ~93 px ones showed no detail); the enlarged view's are over twice that."""
    from explorer.ui.layout import column_widths
    from explorer.ui.panels.error import IMAGE_MIN_PX, enlarged_layout, image_layout

    _, tools = column_widths(1280.0)
    avail = tools - 2 * 8.0 - 14.0          # window padding and the scroll bar
    for width_px, height_px in ((128, 128), (106, 128), (128, 96)):
        per_row, side = image_layout(avail, width_px, height_px)
        assert side >= IMAGE_MIN_PX and per_row * side <= avail
        assert enlarged_layout(1280.0, 700.0, width_px, height_px) >= 2.4 * side
    assert image_layout(600.0, 128, 128)[0] == 3


def test_the_readers_mode_keeps_the_controls_a_step_uses():
    from explorer.ui.reader_controls import OVERLAY_SWITCHES, overlay_sections, view_controls

    lessons, _ = load_all()
    steps = {(lesson.id, step.number): step for lesson in lessons for step in lesson.steps}
    stepper = steps[("limits", 5)]                  # a slice and glyphs, the final image
    assert overlay_sections(stepper, {}) == {"slice", "glyphs"}
    assert overlay_sections(stepper, {"vpls": True}) == {"slice", "glyphs", "vpls"}
    assert overlay_sections(None, {}) == set(OVERLAY_SWITCHES)
    assert view_controls(stepper) == {"frame", "exposure"}
    split = next(step for step in steps.values() if step.view == "split")
    assert "modes" in view_controls(split)
    assert "buffer" in view_controls(steps[("limits", 1)])          # the indirect light
    assert "fly" in view_controls(None) and "screenshot" in view_controls(None)


# --- the real window ---------------------------------------------------------------------

@pytest.fixture(scope="module")
def walk(tmp_path_factory):
    problem = display_problem()
    if problem is not None:
        pytest.skip(problem)
    done = run_child(["tests/reader_walk.py"], tmp_path_factory.mktemp("walk"),
                     timeout=1800)
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


def _shown_to_the_reader(where: list[str]) -> list[str]:
    """The places a string was drawn in the reader's mode: a step on screen, or the
    article once the reader has left the step's settings (the explorer's own panels are
    back then)."""
    return [w for w in where if " after leaving " not in w or w.endswith("[Lesson]")
            or "[Lesson/" in w]


def test_every_string_the_window_draws_for_a_lesson_is_words(walk):
    lessons, _ = load_all()
    assert walk["steps"] == sum(len(lesson.steps) for lesson in lessons)
    assert len(walk["texts"]) > 1000
    bad = {text: (_shown_to_the_reader(where)[:2], window_word_problems(text))
           for text, where in walk["texts"].items()
           if _shown_to_the_reader(where) and window_word_problems(text)}
    assert not bad, json.dumps(bad, ensure_ascii=False, indent=1)[:6000]
    # the walk saw the strings it is there for: captions and hovers of the steps
    texts = set(walk["texts"])
    assert {text for text in texts if text.endswith(": flux per cell [W]")} & {
        "accumulated light: flux per cell [W]",
        *(f"light in flight after step {t}: flux per cell [W]" for t in range(1, 33))}
    assert any(text.startswith("after step ") and ", layer z = " in text for text in texts)
    assert "click to enlarge" in texts


def test_nothing_is_cut_at_1280x720(walk):
    """No label, field or line of text past its panel's edge, no combo whose choice is
    clipped, no dock tab bar shrinking its titles: in every step, and with all panels
    shown after leaving the step's settings."""
    assert not walk["overflows"], json.dumps(walk["overflows"], indent=1)


def test_the_error_images_are_readable_and_a_click_enlarges_them(walk):
    from explorer.ui.panels.error import IMAGE_MIN_PX

    thumbs = [image["rect"] for image in walk["images"] if image["window"] == "Error"]
    assert thumbs
    assert min(x1 - x0 for x0, _, x1, _ in thumbs) >= IMAGE_MIN_PX - 1
    enlarged = walk["enlarged"]
    assert len(enlarged["enlarged"]) == 3, enlarged
    small = max(x1 - x0 for x0, _, x1, _ in enlarged["thumbs"])
    assert min(x1 - x0 for x0, _, x1, _ in enlarged["enlarged"]) >= 2.4 * small
    assert enlarged["closed"]                                   # Escape closes it


def test_after_leaving_the_numbers_are_the_readers_own(walk):
    from explorer.ui.article_try import OWN_FRAME, OWN_NUMBERS

    lessons, _ = load_all()
    where = walk["texts"].get(OWN_NUMBERS, [])
    assert {f"{lesson.id} after leaving [Lesson]" for lesson in lessons} <= set(where)
    assert not [w for w in where if " step " in w]      # never while a step is on screen
    hovers = [text for text, places in walk["texts"].items() if OWN_FRAME in text]
    assert hovers and all(all("after leaving" in w for w in walk["texts"][text])
                          for text in hovers)
