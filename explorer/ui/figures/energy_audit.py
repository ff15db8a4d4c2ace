"""The energy audit as labelled bars: where each configuration gains or loses flux.

One row per audit entry (docs/MODEL.md "Propagation", its energy audit; watts summed over
the colour channels, and over the steps for the per-step terms), one bar per
configuration, each labelled with its value and its share of that side's injected flux.
The accumulated flux counts every step, so it is many times the injected flux: the value
axis turns logarithmic when the bars span more than two decades, or shows shares of the
injected flux instead of watts. The Plots panel draws the same plot
(:func:`draw_audit_plot`).
"""

from __future__ import annotations

import math
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

AUDIT_ROWS = (
    ("RSM", "rsm"),
    ("injected", "injected"),
    ("accumulated (Σ steps)", "accumulated"),
    ("gathered", "gathered"),
    ("border loss (Σ)", "border_loss"),
    ("clamp gain (Σ)", "clamp_gain"),
    ("occluded (Σ)", "occluded"),
    ("reflected (Σ)", "reflected"),
    ("withheld by the budget (Σ)", "budget_withheld"),
)
"""(label, EnergyAudit field); (Σ) rows add up every propagation step."""
NOT_MEASURED = "… not measured yet"
"""Label of a term the frame's audit mode did not measure (the full audit follows)."""
OPTIONAL_ROWS = ("reflected", "budget_withheld")
"""Rows shown only when some side has them (a second bounce, the flux budget)."""
_ROW_HEIGHT = 21.0


def audit_values(audit) -> np.ndarray:
    """One number per AUDIT_ROWS entry: watts summed over colour channels (and over steps
    for the per-step terms); 0 for an entry the audit lacks, NaN for a term its audit
    mode did not measure (explorer.lpv.audit.AUDIT_MODES: the full audit is on its way)."""
    measured_all = getattr(audit, "mode", "full") == "full"
    values = []
    for _, name in AUDIT_ROWS:
        data = getattr(audit, name, None)
        values.append(float(np.sum(data)) if data is not None
                      else 0.0 if measured_all else math.nan)
    return np.array(values, dtype=np.float64)


def audit_series(results: Sequence) -> list[Series]:
    return [Series(label, audit_values(result.audit), style.SIDE_COLOURS[i],
                   injected(result.audit))
            for i, (label, result) in enumerate(zip(result_labels(results), results))]


def shown_rows(series: Sequence[Series]) -> list[int]:
    """Indices of AUDIT_ROWS to draw: all but the optional rows nobody has."""
    return [i for i, (_, name) in enumerate(AUDIT_ROWS)
            if name not in OPTIONAL_ROWS
            or any(s.values[i] != 0.0 and not math.isnan(s.values[i]) for s in series)]


def bar_label(value: float, reference: float, relative: bool) -> str:
    """"0.912 W · 91.2 % of injected", shares first when the axis shows shares; "… not
    measured yet" for a term the frame's audit mode did not measure (NaN)."""
    if math.isnan(value):
        return NOT_MEASURED
    share = style.share_of(value, reference)
    if relative:
        return f"{share} · {style.watts(value)}"
    return f"{style.watts(value)} · {share}" if reference > 0 else style.watts(value)


def audit_plot_height(series: Sequence[Series]) -> float:
    return 70.0 + _ROW_HEIGHT * len(shown_rows(series)) * max(len(series), 1)


def draw_audit_plot(plot_id: str, series: Sequence[Series], width: float, scale: str,
                    relative: bool = False, height: float | None = None) -> None:
    rows = shown_rows(series)
    # a term not measured yet (NaN) draws no bar, only its label
    shown = [np.nan_to_num(np.array([s.values[i] for i in rows]) / (
        s.reference if relative and s.reference > 0 else 1.0)) for s in series]
    everything = np.concatenate(shown) if shown else np.zeros(0)
    chosen = plotting.choose_scale(everything, scale)
    size = imgui.ImVec2(width, height or audit_plot_height(series))
    if not implot.begin_plot(plot_id, size, implot.Flags_.no_menus
                             | implot.Flags_.no_box_select
                             | plotting.legend_flags(len(series), size.y)):
        return
    implot.setup_axes("share of injected flux" if relative else "flux [W]", "", 0,
                      implot.AxisFlags_.invert)
    # Room right of the longest bar for its label (the row names take ~150 pixels).
    labels = [[bar_label(s.values[i], s.reference, relative) for i in rows] for s in series]
    plotting.setup_value_axis(implot.ImAxis_.x1, everything, chosen,
                              plotting.label_room(width - 150.0, sum(labels, [])))
    positions = np.arange(len(rows), dtype=np.float64)
    implot.setup_axis_limits(implot.ImAxis_.y1, -0.6, len(rows) - 0.4, implot.Cond_.always)
    implot.setup_axis_ticks(implot.ImAxis_.y1, [float(p) for p in positions],
                            [AUDIT_ROWS[i][0] for i in rows])
    plotting.legend_above()
    floor = plotting.value_limits(everything, chosen)[0] if chosen == "log" else 0.0
    height_each = 0.8 / max(len(series), 1)
    for k, (s, values) in enumerate(zip(series, shown)):
        ys = positions + (k - (len(series) - 1) / 2.0) * height_each
        spec = style.line_spec(s.colour)
        spec.flags = implot.BarsFlags_.horizontal
        implot.plot_bars(s.label, values, ys, height_each * 0.9, spec)
        for text, value, y in zip(labels[k], values, ys):
            plotting.text_right_of(text, max(float(value), floor), float(y), s.colour)
    implot.end_plot()


def readouts(params: Params, state: State, context) -> dict[str, float]:
    values: dict[str, float] = {}
    for s in audit_series(chosen_results(params, context)):
        side = s.label[0].lower()
        for (_, name), value in zip(AUDIT_ROWS, s.values):
            if math.isnan(value):
                continue          # not measured yet: the readout waits ("…")
            values[f"{side}_{name}"] = float(value)
            if s.reference > 0:
                values[f"{side}_{name}_share"] = float(value / s.reference)
    return values


def draw(params: Params, state: State, width: float, context) -> None:
    results = begin(params, state, context)
    if not results:
        return
    draw_audit_plot("##energy audit", audit_series(results), width, state.scale,
                    state.relative)
    note("Watts summed over the three colour channels; (Σ) rows add up every propagation "
         "step, so the accumulated flux counts the light once per step it stays in the grid.",
         width)
