"""Flux in flight after each propagation step, for configuration A (and B).

The flux of grid_t (docs/MODEL.md "Propagation", its energy audit), one line per
configuration, on a linear axis from 0 or a log axis when the values span more than two
decades; each line ends in a label with its last value and its share of that side's
injected flux, and the legend names what differs between A and B. The Plots panel and the
propagation stepper draw the same plot (:func:`draw_flux_plot`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from imgui_bundle import imgui, implot

from explorer.ui.figures import plotting, style
from explorer.ui.figures.plotting import Series
from explorer.ui.figures.results import (  # noqa: F401  (Params, State: this kind's)
    Params,
    State,
    begin,
    chosen_results,
    injected,
    note,
    result_labels,
)


def flux_per_step(audit) -> np.ndarray:
    """(iterations + 1,) flux of grid_t summed over the colour channels."""
    return np.asarray(audit.per_step, dtype=np.float64).reshape(len(audit.per_step), -1).sum(1)


def flux_series(results: Sequence) -> list[Series]:
    return [Series(label, flux_per_step(result.audit), style.SIDE_COLOURS[i],
                   injected(result.audit))
            for i, (label, result) in enumerate(zip(result_labels(results), results))]


def _shown(series: Series, relative: bool) -> np.ndarray:
    if relative and series.reference > 0:
        return series.values / series.reference * 100.0
    return series.values


def draw_flux_plot(plot_id: str, series: Sequence[Series], size: imgui.ImVec2, scale: str,
                   relative: bool = False, mark: int | None = None) -> None:
    """Flux per step of each series; ``mark`` draws a line at that step with the values."""
    shown = [_shown(s, relative) for s in series]
    everything = np.concatenate(shown) if shown else np.zeros(0)
    chosen = plotting.choose_scale(everything, scale)
    if not implot.begin_plot(plot_id, size, implot.Flags_.no_menus
                             | implot.Flags_.no_box_select
                             | plotting.legend_flags(len(series), size.y)):
        return
    last = max((len(v) for v in shown), default=1) - 1
    implot.setup_axes("step t", "share of injected [%]" if relative else "flux in flight [W]",
                      0, 0)
    # Room right of the last step for the end labels (the y axis takes ~70 pixels).
    ends = [_end_text(s, values, relative) for s, values in zip(series, shown) if len(values)]
    room = plotting.label_room(size.x - 70.0, ends)
    implot.setup_axis_limits(implot.ImAxis_.x1, -0.5, (last + 0.5) / (1.0 - room),
                             implot.Cond_.always)
    plotting.setup_value_axis(implot.ImAxis_.y1, everything, chosen)
    plotting.legend_above()
    for s, values in zip(series, shown):
        xs = np.arange(len(values), dtype=np.float64)
        implot.plot_line(s.label, xs, values,
                         style.line_spec(s.colour, 2.0, implot.Marker_.circle))
        if len(values):
            plotting.text_right_of(_end_text(s, values, relative), float(len(values) - 1),
                                   float(values[-1]), s.colour)
    if mark is not None:
        implot.plot_inf_lines("##t", np.array([float(mark)]),
                              style.line_spec(style.HANDLE, 1.5))
        for _series, values in zip(series, shown):
            if 0 <= mark < len(values):
                implot.plot_scatter("##mark", np.array([float(mark)]),
                                    np.array([values[mark]]),
                                    style.line_spec(style.HANDLE, 1.0, implot.Marker_.circle))
    implot.end_plot()


def _end_text(s: Series, values: np.ndarray, relative: bool) -> str:
    """The label at the end of a line: its last value, and its share of the injected flux."""
    last = float(values[-1])
    if relative:
        return style.percent(last / 100.0)
    if s.reference > 0:
        return f"{style.watts(last)} ({style.share_of(last, s.reference)})"
    return style.watts(last)


def summary(results: Sequence) -> list[str]:
    """One line per configuration: the flux left in flight and the accumulated sum."""
    lines = []
    for s, result in zip(flux_series(results), results):
        values = s.values
        accumulated = float(np.sum(result.audit.accumulated))
        lines.append(f"{s.label.split(':')[0]}: after {len(values) - 1} steps "
                     f"{style.watts(values[-1])} in flight "
                     f"({style.share_of(values[-1], s.reference)} of the injected "
                     f"{style.watts(s.reference)}); the accumulated grid holds "
                     f"{style.watts(accumulated)} = {style.share_of(accumulated, s.reference)} "
                     f"of it, each step counted once.")
    return lines


def readouts(params: Params, state: State, context) -> dict[str, float]:
    values: dict[str, float] = {}
    results = chosen_results(params, context)
    for s, _result in zip(flux_series(results), results):
        side = s.label[0].lower()
        values[f"{side}_injected"] = s.reference
        values[f"{side}_last"] = float(s.values[-1])
        values[f"{side}_last_share"] = float(s.values[-1] / s.reference) if s.reference \
            else 0.0
        values[f"{side}_steps"] = float(len(s.values) - 1)
    return values


def draw(params: Params, state: State, width: float, context) -> None:
    results = begin(params, state, context)
    if not results:
        return
    draw_flux_plot("##flux per step", flux_series(results), style.plot_size(width, 0.5, 320.0),
                   state.scale, state.relative)
    note("\n".join(summary(results)), width)
