"""What the two audit figures (flux per step, energy audit) share: their parameters and
state, which FrameResults they plot, and the legend labels of those results."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from imgui_bundle import imgui

from explorer.figure_params import SIDES  # noqa: F401  (re-export)
from explorer.figure_params import ResultsParams as Params
from explorer.ui import legend
from explorer.ui.figures import plotting, style


@dataclass
class State:
    scale: str
    relative: bool

    @classmethod
    def from_params(cls, params: Params) -> State:
        return cls(params.scale, params.relative)


def chosen_results(params: Params, context) -> tuple:
    """The results ``params.sides`` asks for, of those the context holds."""
    results = tuple(getattr(context, "results", ()) or ())
    return results[:1] if params.sides == "a" else results[:2]


def injected(audit) -> float:
    """Flux injected into the grid, summed over the colour channels."""
    return float(np.sum(audit.injected))


def result_labels(results: Sequence) -> list[str]:
    """Legend labels of one or two FrameResults, naming what differs between them."""
    if len(results) >= 2:
        return list(legend.side_labels(results[0].settings, results[1].settings))
    return [f"A: {legend.describe(results[0].settings)}"] if results else []


def axis_controls(state: State) -> None:
    """The linear/log choice and the share-of-injected switch above a plot."""
    state.scale = plotting.scale_selector(state.scale)
    imgui.same_line(0.0, 24.0)
    _, state.relative = imgui.checkbox("share of injected", state.relative)


def begin(params: Params, state: State, context) -> tuple:
    """The results to plot, after the axis controls; with none, a note and ``()``."""
    results = chosen_results(params, context)
    if not results:
        imgui.text_disabled("No frame yet: this figure fills in once the pipeline has run.")
        return ()
    axis_controls(state)
    return results


def note(text: str, width: float) -> None:
    """A dim paragraph under a figure, wrapped at its width."""
    imgui.push_text_wrap_pos(imgui.get_cursor_pos_x() + width)
    imgui.text_colored(style.MUTED, text)
    imgui.pop_text_wrap_pos()
