"""Every figure a lesson embeds fits the article column it is drawn in, in a window of
1280×720 and of 1600×900 (no figure clipped): drawn at that column's width in a
real window under Xvfb, nothing it submits reaches past the column's right edge."""

from __future__ import annotations

import pytest
from figure_cases import figure_window
from window_cases import display_problem

_PROBLEM = display_problem()
pytestmark = pytest.mark.skipif(_PROBLEM is not None, reason=str(_PROBLEM))

@pytest.fixture(scope="module")
def window():
    win = figure_window(900, 900)
    yield win
    win.close()


def test_every_lesson_figure_fits_its_column_at_both_window_sizes(window):
    from explorer.lessons import load_all
    from explorer.ui.lesson_lint import WINDOWS, column_width, figure_overflows, lesson_figures

    lessons, errors = load_all(check_formula=None)
    assert not errors
    figures = lesson_figures(lessons)
    assert len(figures) >= 10, "the lessons lost their figures"
    for size in WINDOWS:
        assert 300.0 < column_width(size[0]) < 700.0, column_width(size[0])
    too_wide = figure_overflows(window, figures)
    assert not too_wide, "figures wider than their column:\n" + "\n".join(too_wide)
