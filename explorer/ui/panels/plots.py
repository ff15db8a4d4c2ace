"""Plots panel (implot), one tab each: flux in flight per propagation step for A and B,
the energy audit as labelled bars, and the GPU time of each pass.

The flux and audit plots are the lesson figures' own (explorer/ui/figures/flux_per_step.py
and energy_audit.py): a linear/log choice whose "auto" picks log when the values span more
than two decades and otherwise a linear axis from 0, values written on the bars and line
ends with their share of the injected flux, and legends that name what differs between A
and B.
"""

from __future__ import annotations

import numpy as np
from imgui_bundle import imgui, implot

from explorer.ui import widgets
from explorer.ui.figures import plotting
from explorer.ui.figures.energy_audit import audit_series, draw_audit_plot
from explorer.ui.figures.flux_per_step import draw_flux_plot, flux_series
from explorer.ui.state import AppState

TABS = ("flux-per-step", "audit", "timings")
"""The plots (settings.PLOTS) this panel shows as tabs; "error" is the Error panel."""
AUDIT_OF_TAB = {"flux-per-step": "flux", "audit": "full", "timings": "off"}
"""The energy audit (explorer.lpv.audit.AUDIT_MODES) each tab needs while it is shown:
the pipelines measure that much (``runtime.want_audit``). The flux per step comes from
the minimal propagation kernel; only the Energy audit tab needs the full audit."""


def gui_plots(state: AppState) -> None:
    rt = state.runtime
    if rt.frame.result is None:
        imgui.text_disabled("no frame yet")
        return
    results = [rt.frame.result]
    if state.comparing and rt.frame.compare_result is not None:
        results.append(rt.frame.compare_result)
    if not imgui.begin_tab_bar("plots"):
        return
    for name, title, plot in zip(TABS, ("Flux per step", "Energy audit", "GPU time"),
                                 (_flux_plot, _audit_plot, _timings_plot)):
        flags = imgui.TabItemFlags_.set_selected if state.plot_tab == name else 0
        if imgui.begin_tab_item(title, None, flags)[0]:
            state.runtime.want_audit(AUDIT_OF_TAB[name])
            plot(state, results)
            imgui.end_tab_item()
    state.plot_tab = None
    imgui.end_tab_bar()


TITLE_MIN_HEIGHT = 260.0
"""Below this height a plot drops its title (the tab names it) to keep room for its rows."""


def _title(title: str, height: float) -> str:
    """The plot's title, or only its id where the panel is short."""
    return title if height >= TITLE_MIN_HEIGHT else "##" + title


def _axis_controls(state: AppState) -> None:
    state.plot_scale = plotting.scale_selector(state.plot_scale)
    widgets.same_line_if_fits("share of injected", checkbox=True, spacing=24.0)
    _, state.plot_relative = imgui.checkbox("share of injected", state.plot_relative)


def _flux_plot(state: AppState, results: list) -> None:
    _axis_controls(state)
    avail = imgui.get_content_region_avail()
    draw_flux_plot(_title("Flux in flight per propagation step", avail.y), flux_series(results),
                   imgui.ImVec2(avail.x, avail.y - 4), state.plot_scale, state.plot_relative)


def _audit_plot(state: AppState, results: list) -> None:
    _axis_controls(state)
    avail = imgui.get_content_region_avail()
    draw_audit_plot(_title("Energy audit (sum of channels)", avail.y), audit_series(results),
                    avail.x, state.plot_scale, state.plot_relative, avail.y - 4)


def _timings_plot(state: AppState, results: list) -> None:
    result = results[0]
    timings = dict(result.timings_ms)
    methods = dict(result.timing_methods)
    total = sum(timings.values())
    height = imgui.get_content_region_avail().y - 4
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
