"""The default dock layout's sizes: every row of the tool column stays usable from
1280x720 up."""

import pytest

from explorer.ui.layout import PLOT_ROW_MIN_PX, column_widths, tool_rows


@pytest.mark.parametrize("height", [700.0, 860.0, 940.0, 1400.0])
def test_tool_rows_leave_every_row_room(height):
    top, bottom = tool_rows(height)
    middle = height - top - bottom
    # the plot/Error row: readable at 720 (a 300 px plot), a third of a tall window
    assert bottom >= min(PLOT_ROW_MIN_PX, 0.45 * height)
    assert bottom >= 0.32 * height - 1e-9
    # the corrections and Show in scene rows keep at least a quarter of the column each
    assert top >= 0.25 * height and middle >= 0.25 * height
    assert top <= 0.36 * height + 1e-9


def test_tall_windows_keep_the_even_split():
    top, bottom = tool_rows(1400.0)
    assert top == pytest.approx(0.36 * 1400.0)
    assert bottom == pytest.approx(0.32 * 1400.0)


def test_columns_fit_1280():
    article, tools = column_widths(1280.0)
    assert article + tools < 1280.0 - 400.0     # the 3D view keeps at least 400 px


def test_a_short_plot_of_one_series_drops_its_legend():
    from imgui_bundle import implot

    from explorer.ui.figures.plotting import legend_flags

    assert legend_flags(1, 150.0) == implot.Flags_.no_legend     # the 720-px Plots panel
    assert legend_flags(2, 150.0) == 0                           # A and B: tell them apart
    assert legend_flags(1, 400.0) == 0


@pytest.mark.parametrize("width", [640.0, 800.0, 1024.0, 1280.0, 1600.0, 1920.0, 3840.0])
def test_the_default_layout_leaves_the_view_at_least_its_share(width):
    from explorer.ui.layout import VIEW_SHARE, column_widths

    article, tools = column_widths(width)
    assert width - article - tools >= VIEW_SHARE * width - 1e-9
    # From 1280 px up the columns keep their readable widths.
    if width >= 1280.0:
        assert article >= 400.0 and tools >= 290.0
