"""The whole LPV pipeline at a glance, with the frame's own numbers in each stage.

Light → reflective shadow map → (downsample) → injection → propagation ×N → final gather:
one box per stage (docs/MODEL.md, one section each), each with what it holds in the frame
on screen (texels, VPLs, cells, steps) and the flux the energy audit measured there, in
watts summed over the colour channels. Hover a stage (or set ``highlight``) to read what
it does; the chain wraps onto two rows in a narrow column.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from imgui_bundle import imgui

from explorer.figure_params import PIPELINE_STAGES as STAGES
from explorer.figure_params import PipelineParams as Params
from explorer.ui.figures import style


@dataclass
class State:
    highlight: str

    @classmethod
    def from_params(cls, params: Params) -> State:
        return cls(params.highlight)


def _flux(audit, name: str) -> float:
    data = getattr(audit, name, None)
    return 0.0 if data is None else float(np.sum(data))


def readouts(params: Params, state: State, context=None) -> dict[str, float]:
    """The frame's numbers per stage (empty before the first frame)."""
    results = tuple(getattr(context, "results", ()) or ())
    if not results:
        return {}
    result = results[0]
    s = result.settings
    audit = result.audit
    vpls = getattr(result, "vpls", None)
    values = {"rsm_texels": float(s.rsm_size ** 2),
              "vpls": float(vpls.count if vpls is not None else s.rsm_size ** 2),
              "cells": float(s.grid_size ** 3), "iterations": float(s.iterations),
              "rsm_flux": _flux(audit, "rsm"), "injected": _flux(audit, "injected"),
              "accumulated": _flux(audit, "accumulated"),
              "gathered": _flux(audit, "gathered")}
    spec = getattr(result, "grid_spec", None)
    if spec is not None:
        values["cell_size"] = float(spec.cell_size)
    return values


def _lines(values: dict[str, float]) -> dict[str, tuple[str, str, str]]:
    """Three lines for each stage's box: what it holds, its flux, that flux as a share
    of the flux the shadow map reflects."""
    if not values:
        return {key: ("", "", "") for key, _, _ in STAGES}
    n = round(values["cells"] ** (1.0 / 3.0))
    rsm = values["rsm_flux"]

    def share(name: str) -> str:
        return style.share_of(values[name], rsm) + " of RSM" if rsm > 0 else ""

    return {
        "light": ("a spot light", "direct light", "+ one LPV bounce"),
        "rsm": (f"{int(values['rsm_texels'] ** 0.5)}² texels", style.watts(rsm),
                "reflected"),
        "inject": (f"{int(values['vpls']):,} VPLs → {n}³", style.watts(values["injected"]),
                   share("injected")),
        "propagate": (f"×{int(values['iterations'])} steps",
                      "Σ " + style.watts(values["accumulated"]), share("accumulated")),
        "gather": ("pixels read the grid", style.watts(values["gathered"]),
                   share("gathered")),
    }


def draw(params: Params, state: State, width: float, context) -> None:
    values = readouts(params, state, context)
    lines = _lines(values)
    per_row = len(STAGES) if width >= 600.0 else 3
    rows = -(-len(STAGES) // per_row)
    arrow = 18.0
    box_w = (width - arrow * (per_row - 1)) / per_row
    line_h = imgui.get_text_line_height()
    box_h = line_h * 4.5
    origin = imgui.get_cursor_screen_pos()
    draw_list = imgui.get_window_draw_list()
    hovered = None
    for index, (key, title, _) in enumerate(STAGES):
        row, column = divmod(index, per_row)
        x = origin.x + column * (box_w + arrow)
        y = origin.y + row * (box_h + arrow)
        imgui.set_cursor_screen_pos((x, y))
        imgui.invisible_button(f"##stage-{key}", (box_w, box_h))
        if imgui.is_item_hovered():
            hovered = key
        if imgui.is_item_clicked():
            state.highlight = key
        lit = key == (hovered or state.highlight)
        fill = style.with_alpha(style.L1, 0.30 if lit else 0.12)
        draw_list.add_rect_filled((x, y), (x + box_w, y + box_h), style.u32(fill), 5.0)
        draw_list.add_rect((x, y), (x + box_w, y + box_h),
                           style.u32(style.L1, 0.9 if lit else 0.45), 5.0)
        pad = 6.0
        draw_list.push_clip_rect((x, y), (x + box_w, y + box_h), True)
        draw_list.add_text((x + pad, y + pad), style.u32(style.TEXT), title)
        first, second, third = lines[key]
        draw_list.add_text((x + pad, y + pad + line_h * 1.05), style.u32(style.MUTED), first)
        draw_list.add_text((x + pad, y + pad + line_h * 2.05), style.u32(style.HANDLE), second)
        draw_list.add_text((x + pad, y + pad + line_h * 3.05), style.u32(style.MUTED), third)
        draw_list.pop_clip_rect()
        if index < len(STAGES) - 1:
            if column < per_row - 1:           # an arrow to the next box in the row
                ax, ay = x + box_w + 3.0, y + box_h * 0.5
                draw_list.add_triangle_filled((ax, ay - 5), (ax, ay + 5), (ax + arrow - 6, ay),
                                              style.u32(style.MUTED))
            else:                              # down to the next row
                ax, ay = x + box_w * 0.5, y + box_h + 3.0
                draw_list.add_triangle_filled((ax - 5, ay), (ax + 5, ay), (ax, ay + arrow - 6),
                                              style.u32(style.MUTED))
    imgui.set_cursor_screen_pos((origin.x, origin.y + rows * box_h + (rows - 1) * arrow + 6))
    shown = hovered or state.highlight
    text = next((f"{title}: {doc}" for key, title, doc in STAGES if key == shown),
                "Hover a stage to read what it does.")
    start = imgui.get_cursor_pos_y()
    imgui.push_text_wrap_pos(imgui.get_cursor_pos_x() + width)
    imgui.text_colored(style.MUTED, text)
    imgui.pop_text_wrap_pos()
    # the same height whichever stage is described, so the text under it does not jump
    imgui.dummy((width, max(0.0, start + 2.2 * line_h - imgui.get_cursor_pos_y())))
    if not values:
        imgui.text_disabled("The numbers fill in once the pipeline has run.")
