"""Live figures a lesson embeds inline: reusable widgets with parameters.

Each module is one figure kind: a parameter dataclass (``Params``, what a lesson step
sets), a per-instance interactive state (``State``), ``draw(params, state, width,
context)`` drawing into the current imgui window, and ``readouts`` returning the numbers
it shows. :mod:`explorer.ui.figures.registry` lists the kinds and validates lesson
tables; ``python -m explorer.ui.figures KIND --param value --screenshot out.png`` shows
one alone (:mod:`explorer.ui.figures.harness`).
"""

from explorer.figure_params import FigureParamError, ParamInfo
from explorer.ui.figures.host import FigureContext
from explorer.ui.figures.registry import (
    FIGURES,
    FigureKind,
    FigureSpec,
    declared_readouts,
    draw_figure,
    figure_kind,
    make_figure,
    parse_figure,
)

__all__ = ["FIGURES", "FigureContext", "FigureKind", "FigureParamError", "FigureSpec",
           "ParamInfo", "declared_readouts", "draw_figure", "figure_kind", "make_figure",
           "parse_figure"]
