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

import importlib
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from explorer.figure_params import (  # noqa: F401  (re-exported for the window)
    FIGURE_KINDS,
    FIGURE_PARAMS,
    RESERVED_KEYS,
    FigureKindDecl,
    FigureParamError,
    FigureSpec,
    ParamInfo,
    make_figure,
    parse_figure,
    schema,
)
from explorer.ui.figures.host import FigureContext


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
    demo: Mapping[str, Any]
    """A parameter change that changes the figure visibly."""

    @property
    def params(self) -> tuple[ParamInfo, ...]:
        return schema(self.params_class)


def _kind(decl: FigureKindDecl) -> FigureKind:
    """The drawing side of a declared kind, from its module (``decl.module``)."""
    module = importlib.import_module(f"explorer.ui.figures.{decl.module}")
    return FigureKind(decl.name, decl.title,
                      (module.__doc__ or "").strip().split("\n\n")[0], decl.params,
                      module.State.from_params, module.draw, module.readouts, decl.demo)


FIGURES: dict[str, FigureKind] = {decl.name: _kind(decl) for decl in FIGURE_KINDS}
"""Every kind of :data:`explorer.figure_params.FIGURE_KINDS`, in its order."""

USES_RESULTS = tuple(decl.name for decl in FIGURE_KINDS if decl.results)
"""Kinds that plot the FrameResults of the context (A, and B while comparing)."""


def figure_kind(name: str, where: str = "") -> FigureKind:
    """The kind called ``name``, or FigureParamError listing the kinds."""
    if not isinstance(name, str) or name not in FIGURES:
        raise FigureParamError(where + "kind", f"{where}kind: unknown figure kind {name!r}; "
                                               f"choose one of {list(FIGURES)}")
    return FIGURES[name]


def declared_readouts(spec: FigureSpec, results: tuple = ()) -> dict[str, float]:
    """The numbers ``spec`` shows as its step declares it: the state its parameters make
    (nothing dragged, no step played), the kinds of :data:`USES_RESULTS` plotting
    ``results`` (configuration A first, B while comparing). What a lesson check of
    ``figure.<id>.<readout>`` reads (:func:`explorer.lessons.verify.verify_step`)."""
    kind = FIGURES[spec.kind]
    state = kind.make_state(spec.params)
    return dict(kind.readouts(spec.params, state, FigureContext(results=tuple(results))))


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
