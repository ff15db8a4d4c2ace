"""A split view's divider never passes through a mark, its label or the arrow between
them: for every step that splits (its view, or a try-this with ``compare = "split"``),
each labelled mark of the step, drawn where the window draws it, stays clear of the
divider at two aspect ratios of the view."""

from __future__ import annotations

from explorer.lessons import load_all, preview_settings

CLEARANCE = 0.04
"""Least distance of a mark's point from the divider, a fraction of the view's width."""
VIEWS = ((96, 96, 480.0, 480.0), (128, 96, 640.0, 480.0), (96, 112, 480.0, 560.0))
"""(image width, height, drawn width, height): a square and a 4:3 view, and the taller
one of the reader's mode (the article column beside the view)."""


def _text_size(label: str) -> tuple[float, float]:
    return 7.0 * len(label), 15.0      # the window's font at its default size


def _split_cases():
    lessons, errors = load_all(check_formula=None)
    assert not errors
    for lesson in lessons:
        for step in lesson.steps:
            labelled = [mark for mark in step.marks if mark.label]
            if step.view == "split":
                yield lesson, step, None, labelled
            for number, item in enumerate(step.try_this, 1):
                if item.split:
                    yield lesson, step, number, labelled


CASES = list(_split_cases())


def test_the_course_has_split_steps_with_marks():
    assert len(CASES) >= 20
    assert sum(1 for *_, marks in CASES if marks) >= 5


def test_no_divider_crosses_a_mark(ctx):
    from explorer.lpv.pipeline import Pipeline
    from explorer.ui.overlays.marks import placements

    problems = []
    with Pipeline(preview_settings(CASES[0][1]), ctx=ctx) as pipeline:
        for lesson, step, number, marks in CASES:
            if not marks:
                continue
            split_at = 0.5 if step.split_at is None else step.split_at
            settings = preview_settings(step, max_iterations=1)
            if number is not None:
                settings = step.try_this[number - 1].apply(settings)
            for width, height, drawn_w, drawn_h in VIEWS:
                result = pipeline.run(settings.with_changes(width=width, height=height))
                divider = split_at * drawn_w
                for placed in placements(result, marks, (0.0, 0.0), (drawn_w, drawn_h),
                                         _text_size):
                    x0, _, x1, _ = placed.box
                    near = abs(placed.point[0] - divider) < CLEARANCE * drawn_w
                    crossed = x0 < divider < x1
                    # the arrow from the label's side to the point
                    arrow = min(placed.anchor[0], placed.point[0]) < divider < max(
                        placed.anchor[0], placed.point[0])
                    if near or crossed or arrow:
                        where = f"{lesson.number:02d}/{step.number}" + (
                            f" try {number}" if number else "")
                        problems.append(f"{where} {width}x{height}: {placed.label!r} at "
                                        f"x = {placed.point[0] / drawn_w:.2f}, label "
                                        f"{x0 / drawn_w:.2f}..{x1 / drawn_w:.2f}, arrow from "
                                        f"{placed.anchor[0] / drawn_w:.2f}, divider "
                                        f"{split_at:.2f}")
    assert not problems, "\n".join(problems)
