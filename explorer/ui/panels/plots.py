"""Plots panel (implot), one tab each: flux in flight per propagation step for A and B
(log scale), the energy audit as bars, and the GPU time of each pass."""

from __future__ import annotations

import numpy as np
from imgui_bundle import imgui, implot

from explorer.lpv.settings import preset_name
from explorer.ui.state import AppState

AUDIT_ROWS = (
    ("RSM", "rsm"),
    ("injected", "injected"),
    ("accumulated", "accumulated"),
    ("gathered", "gathered"),
    ("border loss", "border_loss"),
    ("clamp gain", "clamp_gain"),
    ("occluded", "occluded"),
)
_LOG_FLOOR = 1e-12


def audit_values(audit) -> np.ndarray:
    """One number per AUDIT_ROWS entry: watts summed over colour channels (and over steps
    for the per-step losses)."""
    values = []
    for _, field in AUDIT_ROWS:
        data = getattr(audit, field, None)
        values.append(float(np.sum(data)) if data is not None else 0.0)
    return np.array(values, dtype=np.float64)


def flux_per_step(audit) -> np.ndarray:
    return np.asarray(audit.per_step, dtype=np.float64).reshape(len(audit.per_step), -1).sum(1)


def gui_plots(state: AppState) -> None:
    rt = state.runtime
    if rt.result is None:
        imgui.text_disabled("no frame yet")
        return
    sides = [("A", rt.result)]
    if state.comparing and rt.compare_result is not None:
        sides.append(("B", rt.compare_result))
    if not imgui.begin_tab_bar("plots"):
        return
    for name, title, plot in (("flux-per-step", "Flux per step", _flux_plot),
                              ("audit", "Energy audit", _audit_plot),
                              ("timings", "GPU time", _timings_plot)):
        flags = imgui.TabItemFlags_.set_selected if state.plot_tab == name else 0
        if imgui.begin_tab_item(title, None, flags)[0]:
            plot(sides, imgui.get_content_region_avail().y - 4)
            imgui.end_tab_item()
    state.plot_tab = None
    imgui.end_tab_bar()


def _flux_plot(sides, height: float) -> None:
    if not implot.begin_plot("Flux in flight per propagation step", (-1, height)):
        return
    implot.setup_axes("step t", "flux [W]", implot.AxisFlags_.auto_fit,
                      implot.AxisFlags_.auto_fit)
    series = [np.maximum(flux_per_step(result.audit), _LOG_FLOOR) for _, result in sides]
    if max(float(ys.max() / ys.min()) for ys in series) > 20.0:
        # Log only when the data spans decades: within one decade implot labels no tick.
        implot.setup_axis_scale(implot.ImAxis_.y1, implot.Scale_.log10)
    for name, result in sides:
        ys = np.maximum(flux_per_step(result.audit), _LOG_FLOOR)
        xs = np.arange(len(ys), dtype=np.float64)
        spec = implot.Spec()
        spec.marker = implot.Marker_.circle
        spec.marker_size = 3.0
        spec.line_weight = 2.0
        implot.plot_line(f"{name}: {_label(result)}", xs, ys, spec)
    implot.end_plot()


def _audit_plot(sides, height: float) -> None:
    """Horizontal bars, one row per audit entry, one bar per side."""
    if not implot.begin_plot("Energy audit (sum of channels)", (-1, height)):
        return
    implot.setup_axes("flux [W]", "", implot.AxisFlags_.auto_fit,
                      implot.AxisFlags_.auto_fit | implot.AxisFlags_.invert)
    implot.setup_legend(implot.Location_.south_east)
    rows = np.arange(len(AUDIT_ROWS), dtype=np.float64)
    implot.setup_axis_ticks(implot.ImAxis_.y1, [float(r) for r in rows],
                            [r[0] for r in AUDIT_ROWS])
    width = 0.8 / len(sides)
    for i, (name, result) in enumerate(sides):
        spec = implot.Spec()
        spec.flags = implot.BarsFlags_.horizontal
        positions = rows + (i - (len(sides) - 1) / 2) * width
        implot.plot_bars(f"{name}: {_label(result)}", audit_values(result.audit), positions,
                         width, spec)
    implot.end_plot()


def _timings_plot(sides, height: float) -> None:
    result = sides[0][1]
    timings = dict(getattr(result, "timings_ms", {}) or {})
    methods = dict(getattr(result, "timing_methods", {}) or {})
    total = sum(timings.values())
    if not implot.begin_plot(f"Time per pass, A (total {total:.1f} ms)", (-1, height)):
        return
    names = list(timings)
    implot.setup_axes("ms", "", implot.AxisFlags_.auto_fit,
                      implot.AxisFlags_.auto_fit | implot.AxisFlags_.invert)
    if names:
        labels = [n + (" (wall)" if methods.get(n) == "wall-clock" else "") for n in names]
        implot.setup_axis_ticks(implot.ImAxis_.y1, [float(i) for i in range(len(names))],
                                labels)
        spec = implot.Spec()
        spec.flags = implot.BarsFlags_.horizontal
        implot.plot_bars("##ms", np.array([timings[n] for n in names], dtype=np.float64),
                         np.arange(len(names), dtype=np.float64), 0.6, spec)
    implot.end_plot()


def _label(result) -> str:
    return preset_name(result.settings.corrections)
