"""Plots panel (implot): flux in flight per propagation step for A and B (log scale), the
energy audit as grouped bars, and the GPU time of each pass."""

from __future__ import annotations

import numpy as np
from imgui_bundle import imgui, implot

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
    height = max((imgui.get_content_region_avail().y - 12) / 3.0, 120.0)
    _flux_plot(sides, height)
    _audit_plot(sides, height)
    _timings_plot(rt.result, height)


def _flux_plot(sides, height: float) -> None:
    if not implot.begin_plot("Flux in flight per step", (-1, height)):
        return
    implot.setup_axes("step t", "flux [W]", implot.AxisFlags_.auto_fit,
                      implot.AxisFlags_.auto_fit)
    implot.setup_axis_scale(implot.ImAxis_.y1, implot.Scale_.log10)
    for name, result in sides:
        ys = np.maximum(flux_per_step(result.audit), _LOG_FLOOR)
        xs = np.arange(len(ys), dtype=np.float64)
        implot.plot_line(f"{name}: {_label(result)}", xs, ys)
    implot.end_plot()


def _audit_plot(sides, height: float) -> None:
    if not implot.begin_plot("Energy audit", (-1, height)):
        return
    implot.setup_axes("", "flux [W]", implot.AxisFlags_.auto_fit, implot.AxisFlags_.auto_fit)
    positions = [float(i) for i in range(len(AUDIT_ROWS))]
    implot.setup_axis_ticks(implot.ImAxis_.x1, positions, [r[0] for r in AUDIT_ROWS])
    width = 0.8 / len(sides)
    for i, (name, result) in enumerate(sides):
        xs = np.arange(len(AUDIT_ROWS), dtype=np.float64) + (i - (len(sides) - 1) / 2) * width
        implot.plot_bars(f"{name}: {_label(result)}", xs, audit_values(result.audit), width)
    implot.end_plot()


def _timings_plot(result, height: float) -> None:
    timings = dict(getattr(result, "timings_ms", {}) or {})
    total = sum(timings.values())
    if not implot.begin_plot(f"GPU time per pass (total {total:.1f} ms)", (-1, height)):
        return
    names = list(timings)
    implot.setup_axes("ms", "", implot.AxisFlags_.auto_fit, implot.AxisFlags_.auto_fit)
    if names:
        implot.setup_axis_ticks(implot.ImAxis_.y1, [float(i) for i in range(len(names))], names)
        spec = implot.Spec()
        spec.flags = implot.BarsFlags_.horizontal
        implot.plot_bars("ms", np.arange(len(names), dtype=np.float64),
                         np.array([timings[n] for n in names], dtype=np.float64), 0.6, spec)
    implot.end_plot()


def _label(result) -> str:
    from explorer.ui.panels.view import _preset_name

    return _preset_name(result.settings.corrections)
