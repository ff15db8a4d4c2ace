"""Small multiples: the same light in two to four panels side by side, one thing varied
(the number of propagation steps, the formulas or the SH order), on one colour scale.

Each panel injects one VPL into a small grid and propagates it with the numpy twin
(explorer/lpv/twin/light_grid.py), like the propagation stepper, and shows the slice through
the light: each cell coloured by the flux it holds, in the accumulated grid or in flight
after the last step. With ``shared_scale`` (the default) the brightest cell of all panels
is white, so the panels compare by brightness; under each panel its total flux.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from imgui_bundle import imgui

from explorer.figure_params import SmallMultiplesParams as Params
from explorer.lpv import constants as K
from explorer.lpv.grid import GridSpec
from explorer.lpv.settings import Corrections
from explorer.lpv.twin.light_grid import inject, propagate_audited
from explorer.lpv.vpl import VplArrays
from explorer.ui.figures import style
from explorer.ui.figures.propagation_stepper import corrections_named

SOURCE_FLUX = 1.0          # watts per colour channel of the one VPL


@dataclass
class State:
    @classmethod
    def from_params(cls, params: Params) -> State:
        return cls()


@dataclass(frozen=True)
class Panel:
    title: str
    slice: np.ndarray
    """(n, n) flux per cell of the slice through the light, channels summed."""
    total: float
    """Flux of the whole grid shown (accumulated or in flight), channels summed."""


@lru_cache(maxsize=32)
def _panel_grid(grid_size: int, source: tuple[int, int, int], normal: str, iterations: int,
                corrections: Corrections, sh_order: int, quantity: str) -> np.ndarray:
    spec = GridSpec((0.0, 0.0, 0.0), 1.0, grid_size)
    axis, sign = "xyz".index(normal[1]), (1.0 if normal[0] == "+" else -1.0)
    n = np.zeros((1, 3))
    n[0, axis] = sign
    vpls = VplArrays(positions=spec.cell_centre(np.array([source])), normals=n,
                     flux=np.full((1, 3), SOURCE_FLUX), depth=np.ones(1), texel_area=1.0)
    grid = inject(vpls, spec, corrections, offset_cells=0.0, sh_order=sh_order)
    steps, accumulated, _ = propagate_audited(grid, corrections, iterations)
    return np.asarray(accumulated if quantity == "accumulated" else steps[-1])


def _title(params: Params, value) -> str:
    if params.vary == "iterations":
        return f"{value} step{'s' if value != 1 else ''}"
    if params.vary == "sh_order":
        return f"L{value}"
    return str(value)


def panels(params: Params) -> list[Panel]:
    """The panels the figure shows, left to right."""
    source = (params.source_x, params.source_y, params.grid_size // 2)
    out = []
    for value in params.panel_values:
        iterations = value if params.vary == "iterations" else params.iterations
        corrections = corrections_named(value if params.vary == "corrections"
                                        else "corrected")
        sh_order = value if params.vary == "sh_order" else 1
        grid = _panel_grid(params.grid_size, source, params.normal, iterations, corrections,
                           sh_order, params.quantity)
        flux = K.SH_FLUX_FACTOR * grid[:, :, :, source[2], 0].sum(axis=0)
        total = float(K.SH_FLUX_FACTOR * grid[..., 0].sum())
        out.append(Panel(_title(params, value), flux, total))
    return out


def readouts(params: Params, state: State, context=None) -> dict[str, float]:
    """``flux_1`` .. ``flux_N``: each panel's total flux (W), and ``last_over_first``."""
    found = panels(params)
    values = {f"flux_{i}": p.total for i, p in enumerate(found, start=1)}
    first = found[0].total
    values["last_over_first"] = found[-1].total / first if first else float("nan")
    return values


def draw(params: Params, state: State, width: float, context) -> None:
    found = panels(params)
    count = len(found)
    gap = style.GAP
    side = max(min((width - gap * (count - 1)) / count, 260.0), 40.0)
    top = max(float(np.abs(p.slice).max()) for p in found) if params.shared_scale else None
    for index, panel in enumerate(found):
        if index:
            imgui.same_line(0.0, gap)
        imgui.begin_group()
        _slice(panel, side, top if top is not None else float(np.abs(panel.slice).max()),
               index)
        imgui.text_colored(style.MUTED, f"{panel.title}: {style.watts(panel.total)}")
        imgui.end_group()
    scale = "one colour scale for all panels" if params.shared_scale else \
        "each panel on its own colour scale"
    what = "accumulated grid" if params.quantity == "accumulated" else \
        "light in flight after the last step"
    imgui.push_text_wrap_pos(imgui.get_cursor_pos_x() + width)
    imgui.text_colored(style.MUTED, f"Flux per cell of the {what}, slice through the light; "
                                    f"{scale}.")
    imgui.pop_text_wrap_pos()


def _slice(panel: Panel, side: float, top: float, index: int) -> None:
    n = panel.slice.shape[0]
    pos = imgui.get_cursor_screen_pos()
    imgui.invisible_button(f"##multiple{index}", imgui.ImVec2(side, side))
    hovered = imgui.is_item_hovered()
    draw = imgui.get_window_draw_list()
    cell = side / n
    style.heat_cells(draw, pos, side, panel.slice, top, 0.9)    # as the stepper's slice
    draw.add_rect(pos, imgui.ImVec2(pos.x + side, pos.y + side), style.u32(style.TEXT, 0.2))
    draw.add_text(imgui.ImVec2(pos.x + 5, pos.y + 3), style.u32(style.TEXT, 0.9), panel.title)
    if hovered:
        mouse = imgui.get_mouse_pos()
        cx = int(np.clip((mouse.x - pos.x) // cell, 0, n - 1))
        cy = int(np.clip(n - 1 - (mouse.y - pos.y) // cell, 0, n - 1))
        imgui.set_tooltip(f"{panel.title}, cell ({cx}, {cy}): "
                          f"{style.watts(float(panel.slice[cx, cy]))}")
