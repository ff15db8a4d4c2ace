"""Every figure a lesson embeds fits the article column it is drawn in, in a window of
1280×720 and of 1600×900 (issue #25: no clipped figure): drawn at that column's width in a
real window under Xvfb, nothing it submits reaches past the column's right edge."""

from __future__ import annotations

import pytest

from figure_cases import figure_window
from window_cases import display_problem

_PROBLEM = display_problem()
pytestmark = pytest.mark.skipif(_PROBLEM is not None, reason=str(_PROBLEM))

WINDOWS = ((1280, 720), (1600, 900))
SLACK_PX = 1.0
"""Rounding of imgui's layout (item rectangles are floats)."""


def _lesson_figures() -> list:
    from explorer.lessons import load_all

    lessons, errors = load_all(check_formula=None)
    assert not errors
    return [(f"{lesson.id}/{step.number}/{spec.instance_id}", spec)
            for lesson in lessons for step in lesson.steps for spec in step.figures]


def column_width(window_width: int) -> float:
    """The article's text column in a window this wide: the article dock of the default
    layout, less the window's padding on both sides and the scroll bar, laid out by
    explorer/ui/article.py's column_width."""
    from imgui_bundle import imgui

    from explorer.ui import article
    from explorer.ui.layout import column_widths

    style = imgui.get_style()
    dock = column_widths(float(window_width))[0]
    return article.column_width(dock - 2.0 * style.window_padding.x - style.scrollbar_size)


@pytest.fixture(scope="module")
def window():
    win = figure_window(900, 900)
    yield win
    win.close()


def test_every_lesson_figure_fits_its_column_at_both_window_sizes(window):
    figures = _lesson_figures()
    assert len(figures) >= 10, "the lessons lost their figures"
    too_wide = []
    for size in WINDOWS:
        width = column_width(size[0])
        assert 300.0 < width < 700.0, width
        for where, spec in figures:
            window.render(spec, frames=3, figure_width=width)
            (left, _), _ = window.rect
            over = window.drawn_right - (left + width)
            if over > SLACK_PX:
                too_wide.append(f"{where} ({spec.kind}) at {size[0]}×{size[1]}: "
                                f"{over:.0f} px past a {width:.0f} px column")
    assert not too_wide, "figures wider than their column:\n" + "\n".join(too_wide)
