"""Propagation, step by step: a point light in a small grid, one step t at a time.

One VPL is injected at a cell of a small grid (numpy twin, explorer/lpv/twin/light_grid.py,
with the chosen corrections) and propagated; the figure shows the slice through the
source at step t, each cell coloured by the flux it holds and marked with a glyph of
where its light is heading (its intensity lobe, or an arrow along its band-1 vector), and
beside it the flux in flight per step with t marked. Scrub t with the slider or press
Play; the line under the slice balances the books: flux in flight + what left through the
border − what the front-face clamp added = the injected flux.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from imgui_bundle import imgui

from explorer.figure_params import STEPPER_CORRECTIONS as CORRECTIONS
from explorer.figure_params import STEPPER_GLYPHS as GLYPHS
from explorer.figure_params import PropagationStepperParams as Params
from explorer.lpv import constants as K
from explorer.lpv.audit import GridAudit
from explorer.lpv.grid import GridSpec
from explorer.lpv.settings import PRESETS, Corrections
from explorer.lpv.twin.light_grid import inject, propagate_audited
from explorer.lpv.vpl import VplArrays
from explorer.ui import glyphs, legend, widgets
from explorer.ui.figures import plotting, style
from explorer.ui.figures.flux_per_step import draw_flux_plot
from explorer.ui.figures.plotting import Series

"""A preset, or the corrected preset with one switch off."""
PLAY_RATE = 3.0            # steps per second while playing
SOURCE_FLUX = 1.0          # watts per colour channel of the one VPL


@dataclass
class State:
    step: int
    playing: bool
    scale: str
    glyph: str
    clock: float = 0.0

    @classmethod
    def from_params(cls, params: Params) -> State:
        return cls(params.step, params.play, params.scale, params.glyph)


# ----------------------------------------------------------------------------- the numbers


def corrections_named(name: str) -> Corrections:
    """A :data:`CORRECTIONS` choice as switches."""
    if name in PRESETS:
        return PRESETS[name]
    switch = name.removesuffix(" off")
    if switch not in Corrections.names():
        raise ValueError(f"corrections must be one of {CORRECTIONS}, got {name!r}")
    return dataclasses.replace(PRESETS["corrected"], **{switch: False})


@dataclass(frozen=True)
class Run:
    steps: list[np.ndarray]        # grid_0..grid_N, (3, n, n, n, 4)
    audit: GridAudit
    source: tuple[int, int, int]

    @property
    def flux(self) -> np.ndarray:
        """(N + 1,) flux in flight per step, summed over the channels."""
        return self.audit.per_step.sum(axis=1)


@lru_cache(maxsize=16)
def _run(grid_size: int, source: tuple[int, int, int], normal: str, iterations: int,
         corrections: Corrections) -> Run:
    spec = GridSpec((0.0, 0.0, 0.0), 1.0, grid_size)
    axis, sign = "xyz".index(normal[1]), (1.0 if normal[0] == "+" else -1.0)
    n = np.zeros((1, 3))
    n[0, axis] = sign
    vpls = VplArrays(positions=spec.cell_centre(np.array([source])), normals=n,
                     flux=np.full((1, 3), SOURCE_FLUX), depth=np.ones(1), texel_area=1.0)
    grid = inject(vpls, spec, corrections, offset_cells=0.0)
    steps, _, audit = propagate_audited(grid, corrections, iterations)
    return Run(steps, audit, source)


def run(params: Params) -> Run:
    """The injection and propagation the figure shows (cached per parameters)."""
    source = (params.source_x, params.source_y, params.grid_size // 2)
    return _run(params.grid_size, source, params.normal, params.iterations,
                corrections_named(params.corrections))


def cell_flux(grid: np.ndarray, z: int) -> np.ndarray:
    """(n, n) flux held by each cell of slice ``z``, summed over the channels (2√π·f0)."""
    return K.SH_FLUX_FACTOR * np.asarray(grid)[:, :, :, z, 0].sum(axis=0)


def readouts(params: Params, state: State, context=None) -> dict[str, float]:
    result = run(params)
    t = min(state.step, params.iterations)
    audit = result.audit
    injected = float(audit.injected.sum())
    in_flight = float(result.flux[t])
    lost = float(audit.border_loss[:t].sum())
    gained = float(audit.clamp_gain[:t].sum())
    return {"step": float(t), "injected": injected, "in_flight": in_flight,
            "in_flight_share": in_flight / injected, "border_loss": lost,
            "clamp_gain": gained, "balance": in_flight + lost - gained,
            "accumulated": float(sum(result.flux[:t + 1]))}


# ----------------------------------------------------------------------------- drawing


def draw(params: Params, state: State, width: float, context) -> None:
    result = run(params)
    state.playing, state.step, state.clock = widgets.playback(
        state.playing, state.step, params.iterations, state.clock, PLAY_RATE, width)
    imgui.set_next_item_width(140.0)
    _, state.glyph = widgets.combo("glyph", state.glyph, GLYPHS)
    imgui.same_line(0.0, 24.0)
    state.scale = plotting.scale_selector(state.scale)
    if style.side_by_side(width, 260.0):
        side = min((width - style.GAP) / 2.0, 440.0)
        _slice(params, state, result, side)
        imgui.same_line(0.0, style.GAP)
        _flux(params, state, result, imgui.ImVec2(width - side - style.GAP, side))
    else:
        _slice(params, state, result, min(width, 440.0))
        _flux(params, state, result, style.plot_size(width, 0.6, 300.0))
    _balance(params, state, width)


def _slice(params: Params, state: State, result: Run, side: float) -> None:
    t = min(state.step, params.iterations)
    grid = result.steps[t]
    z = result.source[2]
    n = params.grid_size
    flux = cell_flux(grid, z)
    top = float(np.abs(flux).max())
    pos = imgui.get_cursor_screen_pos()
    size = imgui.ImVec2(side, side)
    imgui.invisible_button("##slice", size)
    hovered = imgui.is_item_hovered()
    draw = imgui.get_window_draw_list()
    cell = side / n
    # Colour: the cell's flux relative to this step's brightest cell, short of the map's
    # white end so that the white glyphs stay visible on the brightest cell.
    style.heat_cells(draw, pos, side, flux, top, 0.8, outline_alpha=0.08)
    sx, sy = result.source[:2]
    s0 = imgui.ImVec2(pos.x + sx * cell, pos.y + (n - 1 - sy) * cell)
    draw.add_rect(s0, imgui.ImVec2(s0.x + cell, s0.y + cell), style.u32(style.HANDLE), 0.0,
                  2.0)
    if state.glyph == "lobe":
        glyphs.draw_lobe_glyphs(draw, grid, z, pos, size, style.u32(style.TEXT, 0.9),
                                style.u32(style.NEGATIVE, 0.95))
    elif state.glyph == "arrow":
        glyphs.draw_arrow_glyphs(draw, grid, z, pos, size, style.u32(style.TEXT, 0.9))
    draw.add_text(imgui.ImVec2(pos.x + 6, pos.y + 4), style.u32(style.TEXT, 0.9),
                  f"after step {t}, layer z = {z}")
    if hovered:
        mouse = imgui.get_mouse_pos()
        cx = int(np.clip((mouse.x - pos.x) // cell, 0, n - 1))
        cy = int(np.clip(n - 1 - (mouse.y - pos.y) // cell, 0, n - 1))
        imgui.set_tooltip(f"cell ({cx}, {cy}, {z}) at step {t}: "
                          f"{style.watts(float(flux[cx, cy]))}")


def _flux(params: Params, state: State, result: Run, size: imgui.ImVec2) -> None:
    corrections = corrections_named(params.corrections)
    label = legend.describe_corrections(corrections)
    series = [Series(label, result.flux, style.SIDE_COLOURS[0],
                     float(result.audit.injected.sum()))]
    imgui.begin_group()
    draw_flux_plot("##stepper flux", series, size, state.scale, mark=state.step)
    imgui.end_group()


def _balance(params: Params, state: State, width: float) -> None:
    r = readouts(params, state)
    imgui.push_text_wrap_pos(imgui.get_cursor_pos_x() + width)
    imgui.text(f"Step t = {int(r['step'])}: {style.watts(r['in_flight'])} in flight "
               f"({style.percent(r['in_flight_share'])} of the injected "
               f"{style.watts(r['injected'])}).")
    if abs(r["balance"] - r["injected"]) <= 1e-9 * r["injected"]:
        verdict = "the injected flux: these formulas conserve it"
    else:
        verdict = (f"not the injected {style.watts(r['injected'])}: these formulas change the "
                   f"flux at every step")
    imgui.text_colored(style.MUTED,
                       f"In flight {style.watts(r['in_flight'])} + left through the border "
                       f"{style.watts(r['border_loss'])} − added by the front-face clamp "
                       f"{style.watts(r['clamp_gain'])} = {style.watts(r['balance'])}, "
                       f"{verdict}. Colour: flux per cell relative to this step's brightest "
                       f"cell.")
    imgui.pop_text_wrap_pos()
