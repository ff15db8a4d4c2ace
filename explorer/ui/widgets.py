"""Small imgui helpers the panels share (colours, formulas, combos, images)."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from imgui_bundle import imgui

from explorer.ui.textures import diverging, heat

ACCENT = imgui.ImVec4(0.33, 0.62, 0.98, 1.0)
DIM = imgui.ImVec4(0.62, 0.64, 0.68, 1.0)
GOOD = imgui.ImVec4(0.45, 0.85, 0.55, 1.0)
WARN = imgui.ImVec4(1.0, 0.75, 0.3, 1.0)
ERROR = imgui.ImVec4(1.0, 0.42, 0.38, 1.0)
LEVEL_COLOURS = {"info": DIM, "warning": WARN, "error": ERROR}
SCALE_BAR_WIDTH = 18.0
"""Width in pixels of the colour bar beside a false-colour image."""


def button_active(label: str, active: bool, size=(0, 0)) -> bool:
    """A button drawn highlighted when ``active`` (e.g. the preset in effect)."""
    if active:
        imgui.push_style_color(imgui.Col_.button, imgui.ImVec4(0.20, 0.42, 0.75, 1.0))
    pressed = imgui.button(label, size)
    if active:
        imgui.pop_style_color()
    return pressed


def same_line_if_fits(label: str, checkbox: bool = False, field: float = 0.0,
                      spacing: float = -1.0) -> None:
    """Continue a row of widgets on this line if the next widget fits, else wrap. ``field``:
    the width of a slider or input in front of the label; ``spacing``: the gap before it
    (-1: the style's)."""
    style = imgui.get_style()
    width = imgui.calc_text_size(label).x + style.frame_padding.x * 2 + field
    if checkbox:
        width += imgui.get_frame_height() + style.item_inner_spacing.x
    imgui.same_line(0.0, spacing)
    if imgui.get_content_region_avail().x < width:
        imgui.new_line()


MIN_FIELD_WIDTH = 80.0
"""A field narrowed by :func:`fit_next_item` keeps at least this width (pixels)."""


def fit_next_item(label: str) -> None:
    """Narrow the next field (slider, combo, input) so that it and its label, drawn right
    of it, end within the column: imgui's item width (about 65 % of the window) plus a
    long label runs past the right edge of a narrow panel (the tool column at 1280×720).
    A field whose label fits keeps the usual width, so the fields stay aligned."""
    text = label.split("##")[0]
    room = (imgui.get_content_region_avail().x - imgui.calc_text_size(text).x
            - imgui.get_style().item_inner_spacing.x)
    imgui.set_next_item_width(max(min(imgui.calc_item_width(), room), MIN_FIELD_WIDTH))


def dim_text_wrapped(text: str) -> None:
    imgui.push_style_color(imgui.Col_.text, DIM)
    imgui.text_wrapped(text)
    imgui.pop_style_color()


def caption(text: str, highlighted: bool = False) -> None:
    imgui.text_colored(ACCENT if highlighted else DIM, text)


def flux_text(text: str) -> None:
    imgui.text_colored(WARN, "flux:")
    imgui.same_line()
    dim_text_wrapped(text)


def formula(formulas, latex: str, active: bool = True, tooltip: str | None = None,
            scale: float = 1.0) -> None:
    """A typeset formula (texture from the FormulaCache), or its LaTeX source as text."""
    entry = formulas.get(latex, scale) if formulas is not None else None
    tint = imgui.ImVec4(1, 1, 1, 1) if active else imgui.ImVec4(1, 1, 1, 0.45)
    if entry is not None and entry.texture_id:
        width, height = float(entry.width), float(entry.height)
        avail = imgui.get_content_region_avail().x
        if width > avail > 8:  # shrink wide formulas to the column
            height *= avail / width
            width = avail
        imgui.image_with_bg(imgui.ImTextureRef(entry.texture_id), (width, height),
                            (0, 0), (1, 1), imgui.ImVec4(0, 0, 0, 0), tint)
    else:
        imgui.push_style_color(imgui.Col_.text, tint if active else DIM)
        imgui.text_wrapped(latex)
        imgui.pop_style_color()
    if tooltip and imgui.is_item_hovered():
        imgui.set_tooltip(tooltip)


def combo(label: str, value: str, choices) -> tuple[bool, str]:
    """A combo over string choices; returns (changed, new value)."""
    choices = list(choices)
    index = choices.index(value) if value in choices else 0
    changed, index = imgui.combo(label, index, choices)
    return changed, choices[index]


def help_marker(text: str) -> None:
    imgui.same_line()
    imgui.text_disabled("(?)")
    if imgui.is_item_hovered():
        imgui.set_tooltip(text)


_animating = False


def animating() -> bool:
    """Whether a playback drawn since the last call is playing (the window then draws
    the next frame without waiting for input); resets."""
    global _animating
    playing, _animating = _animating, False
    return playing


def playback(playing: bool, step: int, last: int, clock: float, rate: float,
             width: float | None = None) -> tuple[bool, int, float]:
    """Play/Pause and a step slider 0..``last``; while playing, ``clock`` (fractional
    steps) advances by ``rate`` steps per second and the step wraps around. Returns the new
    (playing, step, clock); moving the slider pauses. ``width``: the row's width (a
    figure's column); None: to the panel's right edge."""
    start = imgui.get_cursor_pos_x()
    if imgui.button("Pause" if playing else "Play"):
        playing = not playing
    imgui.same_line()
    if width is None:
        imgui.set_next_item_width(-1)
    else:    # what is left of the row after the button, however wide the window is
        imgui.set_next_item_width(max(start + width - imgui.get_cursor_pos_x(), 40.0))
    changed, value = imgui.slider_int("##t", min(step, last), 0, last, "t = %d")
    if changed:
        step, playing = value, False
    if playing:
        global _animating
        _animating = True
        clock += imgui.get_io().delta_time * rate
        if clock >= 1.0:
            step = (step + int(clock)) % (last + 1)
            clock %= 1.0
    return playing, step, clock


def scale_bar(draw, pos, height: float, top: float, signed: bool = False,
              value_at=None) -> None:
    """A vertical colour-scale bar with ticks: heat from 0 (bottom) to ``top``, or with
    ``signed`` the diverging map from −top (bottom) to +top. ``value_at(fraction)``: the
    value at a height fraction for the labels, when the scale is not linear."""
    steps = _SCALE_BAR_STEPS
    low = -top if signed else 0.0
    colours = [_u32(rgb) for rgb in _scale_bar_colours(signed)]

    for i in range(steps):
        t0, t1 = i / steps, (i + 1) / steps
        c0, c1 = colours[i], colours[i + 1]
        y0, y1 = pos.y + t0 * height, pos.y + t1 * height
        draw.add_rect_filled_multi_color((pos.x, y0), (pos.x + SCALE_BAR_WIDTH, y1),
                                         c0, c0, c1, c1)
    white = imgui.get_color_u32(imgui.ImVec4(1, 1, 1, 0.9))
    for frac in (0.0, 0.25, 0.5, 0.75, 1.0):
        y = pos.y + (1.0 - frac) * height
        draw.add_line((pos.x + SCALE_BAR_WIDTH, y), (pos.x + SCALE_BAR_WIDTH + 4, y), white)
        value = value_at(frac) if value_at is not None else low + (top - low) * frac
        label = f"{value:.2g}"
        draw.add_text((pos.x + SCALE_BAR_WIDTH + 6, min(y, pos.y + height - 14) - 6), white,
                      label)


_SCALE_BAR_STEPS = 32


@lru_cache(maxsize=2)
def _scale_bar_colours(signed: bool) -> tuple[tuple[float, float, float], ...]:
    """The bar's colours from its top down, at each of its step edges: they depend only
    on the map (the range changes the labels), so they are computed once per map."""
    def colour(frac: float):
        if signed:
            return diverging(np.array(2.0 * frac - 1.0), 1.0)
        return heat(frac)

    fractions = (1.0 - i / _SCALE_BAR_STEPS for i in range(_SCALE_BAR_STEPS + 1))
    return tuple(tuple(float(v) for v in colour(f)[:3]) for f in fractions)


def _u32(rgb) -> int:
    return imgui.get_color_u32(imgui.ImVec4(float(rgb[0]), float(rgb[1]), float(rgb[2]), 1.0))
