"""Value axes with a sensible default range, shared by every plot of flux.

A linear axis fitted tightly to the data makes a 3 % change fill the plot; a log axis
over data within one decade shows no tick. So: "auto" picks a log axis when the positive
values span more than :data:`LOG_DECADES` decades, and otherwise a linear axis that starts
at 0 (or below, for negative values), so the height of a point is its size.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from imgui_bundle import imgui, implot

from explorer.figure_params import SCALES  # noqa: F401  (re-export: the plots' axis choices)
from explorer.ui.figures import style

LOG_DECADES = 2.0
_HEADROOM = 1.08


def choose_scale(values, requested: str = "auto") -> str:
    """"linear" or "log" for ``values``: ``requested`` unless it is "auto"; log needs
    positive values (a log axis cannot show the others)."""
    if requested not in SCALES:
        raise ValueError(f"scale must be one of {SCALES}, got {requested!r}")
    if requested != "auto":
        return requested
    positive = np.asarray(values, np.float64)
    positive = positive[np.isfinite(positive) & (positive > 0)]
    if positive.size < 2:
        return "linear"
    return "log" if math.log10(positive.max() / positive.min()) > LOG_DECADES else "linear"


def value_limits(values, scale: str, room: float = 0.0) -> tuple[float, float]:
    """Axis limits for ``values``: linear from 0 (or the most negative value) to a little
    above the largest; log from the decade below the smallest positive value to the decade
    above the largest. ``room`` in [0, 1): the share of the axis kept free above the
    largest value (for labels at the ends of bars and lines)."""
    data = np.asarray(values, np.float64)
    data = data[np.isfinite(data)]
    keep = 1.0 - min(max(room, 0.0), 0.9)
    if scale == "log":
        positive = data[data > 0]
        if positive.size == 0:
            return 0.1, 1.0
        low = 10.0 ** math.floor(math.log10(positive.min()))
        if room > 0.0:
            high = 10.0 ** (math.log10(low) + math.log10(positive.max() / low) / keep)
        else:
            high = 10.0 ** math.ceil(math.log10(positive.max() * _HEADROOM))
        return low, max(high, low * 10.0)
    if data.size == 0:
        return 0.0, 1.0
    low = min(0.0, float(data.min()) * _HEADROOM)
    high = max(float(data.max()) * _HEADROOM, 0.0)
    if room > 0.0:
        high = low + (high - low) / keep
    if high <= low:
        high = low + 1.0
    return low, high


def label_room(axis_pixels: float, labels) -> float:
    """The share of an axis ``axis_pixels`` long that the widest of ``labels`` needs
    (with the gap :func:`text_right_of` leaves), at most 0.6."""
    widest = max((imgui.calc_text_size(text).x for text in labels), default=0.0)
    return min((widest + 12.0) / max(axis_pixels, 1.0), 0.6)


def setup_value_axis(axis: int, values, scale: str, room: float = 0.0) -> None:
    """Scale and limits (set every frame, so new data refits) of an implot axis."""
    if scale == "log":
        implot.setup_axis_scale(axis, implot.Scale_.log10)
    low, high = value_limits(values, scale, room)
    implot.setup_axis_limits(axis, low, high, implot.Cond_.always)


def scale_selector(current: str, label: str = "axis") -> str:
    """Inline radio buttons auto / linear / log; returns the choice."""
    imgui.push_id(label)
    imgui.align_text_to_frame_padding()
    imgui.text_colored(style.MUTED, f"{label}:")
    for scale in SCALES:
        imgui.same_line()
        if imgui.radio_button(scale, current == scale):
            current = scale
    imgui.pop_id()
    return current


LEGEND_MIN_HEIGHT = 200.0
"""A plot shorter than this shows a legend only when it has several series to tell apart."""


def legend_flags(series_count: int, height: float) -> int:
    """``begin_plot`` flags for the legend: none in a short plot of one series (its row
    would take the room of the bars; the panel names configuration A)."""
    return implot.Flags_.no_legend if series_count < 2 and height < LEGEND_MIN_HEIGHT else 0


def legend_above() -> None:
    """The plot's legend in one row above the plot area, outside it: inside, it covered
    the bars' and line ends' value labels in a short plot."""
    implot.setup_legend(implot.Location_.north,
                        implot.LegendFlags_.outside | implot.LegendFlags_.horizontal)


@dataclass(frozen=True)
class Series:
    """One configuration's data in a plot: its legend label and colour."""

    label: str
    values: np.ndarray
    colour: imgui.ImVec4
    reference: float = 0.0
    """The flux the values are compared with (the side's injected flux); 0 = none."""


def text_right_of(text: str, x: float, y: float, colour: imgui.ImVec4) -> None:
    """A plot label whose left edge sits just right of (x, y)."""
    width = imgui.calc_text_size(text).x
    implot.push_style_color(implot.Col_.inlay_text, colour)
    implot.plot_text(text, x, y, imgui.ImVec2(width / 2.0 + 6.0, 0.0))
    implot.pop_style_color()
