"""Data the figure tests share: FrameResult stand-ins built from the numpy twin."""

from __future__ import annotations

from types import SimpleNamespace

from explorer.lpv.audit import EnergyAudit
from explorer.lpv.settings import PRESETS, Settings
from explorer.ui.figures import make_figure, propagation_stepper


def synthetic_result(corrections: str, iterations: int = 6):
    """A FrameResult stand-in (settings and an EnergyAudit) from the numpy twin."""
    params = make_figure("propagation-stepper", iterations=iterations,
                         corrections=corrections).params
    audit = propagation_stepper.run(params).audit
    full = EnergyAudit.from_grid_audit(audit, rsm=audit.injected,
                                       gathered=0.4 * audit.injected)
    return SimpleNamespace(settings=Settings(corrections=PRESETS[corrections]), audit=full)


def figure_window(width: int, height: int):
    """A hidden one-figure window (explorer/ui/figures/harness.py) whose audit figures
    plot the corrected and the original preset's synthetic frames; the caller closes it."""
    from explorer.ui.figures.harness import FigureWindow

    window = FigureWindow(width, height, visible=False)
    window.context.results = (synthetic_result("corrected"), synthetic_result("original"))
    return window
