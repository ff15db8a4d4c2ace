"""The figure kinds a lesson can embed, their parameter schemas, and drawing one.

A lesson step lists its figures as TOML tables::

    [[steps.figures]]
    kind = "clamped-cosine"
    normal_deg = 30
    caption = "Drag the normal: the L1 lobe follows, its negative tail with it."

:func:`parse_figure` checks such a table against :data:`FIGURES` (errors name the field);
:func:`draw_figure` draws the resulting :class:`FigureSpec` into the current imgui window
at a given width, keeping its interactive state in a :class:`FigureContext`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

from explorer.ui.figures import (
    cell_faces,
    clamped_cosine,
    energy_audit,
    flux_per_step,
    pipeline_overview,
    propagation_stepper,
    rsm_texel,
    small_multiples,
)
from explorer.ui.figures.host import FigureContext
from explorer.figure_params import (  # noqa: F401  (re-exported for the window)
    FIGURE_PARAMS,
    RESERVED_KEYS,
    FigureParamError,
    FigureSpec,
    ParamInfo,
    make_figure,
    parse_figure,
    schema,
)

@dataclass(frozen=True)
class FigureKind:
    """One reusable figure: its parameters, its per-instance state and how it draws."""

    name: str
    title: str
    summary: str
    params_class: type
    make_state: Callable[[Any], Any]
    """params -> the instance's interactive state (starts from the parameters)."""
    draw: Callable[[Any, Any, float, FigureContext], None]
    """(params, state, width in pixels, context): draws at the imgui cursor."""
    readouts: Callable[[Any, Any, FigureContext], dict[str, float]]
    """(params, state, context) -> the numbers the figure shows now, by name, so prose
    next to it can quote them as they change."""

    @property
    def params(self) -> tuple[ParamInfo, ...]:
        return schema(self.params_class)


def _kind(module, name: str, title: str) -> FigureKind:
    return FigureKind(name, title, (module.__doc__ or "").strip().split("\n\n")[0],
                      module.Params, module.State.from_params, module.draw, module.readouts)


FIGURES: dict[str, FigureKind] = {kind.name: kind for kind in (
    _kind(clamped_cosine, "clamped-cosine", "Clamped cosine and its SH projections"),
    _kind(cell_faces, "cell-faces", "A cell's neighbour, its five faces and their solid "
                                    "angles"),
    _kind(propagation_stepper, "propagation-stepper", "Propagation, step by step"),
    _kind(small_multiples, "small-multiples", "Small multiples: one thing varied, side by "
                                              "side"),
    _kind(rsm_texel, "rsm-texel", "An RSM texel on a tilted surface"),
    _kind(energy_audit, "energy-audit", "Energy audit"),
    _kind(flux_per_step, "flux-per-step", "Flux in flight per propagation step"),
    _kind(pipeline_overview, "pipeline", "The LPV pipeline at a glance"),
)}


USES_RESULTS = ("energy-audit", "flux-per-step", "pipeline")
"""Kinds that plot the FrameResults of the context (A, and B while comparing)."""


def figure_kind(name: str, where: str = "") -> FigureKind:
    """The kind called ``name``, or FigureParamError listing the kinds."""
    if not isinstance(name, str) or name not in FIGURES:
        raise FigureParamError(where + "kind", f"{where}kind: unknown figure kind {name!r}; "
                                               f"choose one of {list(FIGURES)}")
    return FIGURES[name]


def draw_figure(spec: FigureSpec, width: float, context: FigureContext
                ) -> tuple[tuple[float, float], tuple[float, float]]:
    """Draw ``spec`` at the imgui cursor, ``width`` pixels wide, then its caption.
    Returns the screen rectangle the figure (caption included) covers."""
    from imgui_bundle import imgui

    from explorer.ui import widgets

    kind = FIGURES[spec.kind]
    state = context.state_for(spec.instance_id, spec.kind, spec.params, kind.make_state)
    imgui.push_id(f"figure:{spec.instance_id}")
    start = imgui.get_cursor_screen_pos()
    imgui.begin_group()
    kind.draw(spec.params, state, float(width), context)
    if spec.caption:
        imgui.push_text_wrap_pos(imgui.get_cursor_pos_x() + float(width))
        widgets.dim_text_wrapped(spec.caption)
        imgui.pop_text_wrap_pos()
    imgui.end_group()
    end = imgui.get_item_rect_max()
    imgui.pop_id()
    return (start.x, start.y), (max(end.x, start.x + float(width)), end.y)
