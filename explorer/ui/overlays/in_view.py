"""The overlays' part of the View panel (imgui): the texture to show per side, and, over
the image, the slice's colour bar, the hover tooltip, click-to-pick and ctrl + wheel to
move the slice. The View panel calls :func:`shown_texture` per side and
:func:`over_image` once."""

from __future__ import annotations

import sys
from dataclasses import dataclass, replace

import numpy as np
from imgui_bundle import imgui

from explorer.ui.overlays import quantities as Q
from explorer.ui.overlays.describe import cell_rows, pixel_rows
from explorer.ui.overlays.picking import (
    CellInfo,
    PickInfo,
    pick_cell,
    pick_pixel,
    slice_hit,
    view_pixel,
)
from explorer.ui.state import AppState

CLICK_SLOP = 4.0        # pixels the mouse may move between press and release of a click
_BAR_ROOM = 84.0        # width of the colour bar with its labels


def side_result(state: AppState, side: str):
    """The finished frame ``side`` shows: A's, B's, or a small multiples' further view's
    (its picture's)."""
    rt = state.runtime
    if side in ("A", "B"):
        return rt.frame.result if side == "A" else rt.frame.compare_result
    picture = rt.frame.pictures.get(side)
    return None if picture is None else picture.result


def shown_texture(state: AppState, side: str, texture: int, bottom_first: bool,
                  version: object = None) -> tuple[int, bool]:
    """(texture, stored bottom row first) the view draws for ``side``: the overlays
    composited over ``texture`` (holding ``version``) when any is shown, else
    ``texture`` itself."""
    rt, overlays = state.runtime, state.overlays
    result = side_result(state, side)
    if (not overlays.any_shown or rt.services.compositor is None or result is None
            or result.gbuffer_position is None):
        return texture, bottom_first
    try:
        return rt.services.compositor.compose(side, result, texture, not bottom_first, overlays,
                                     version), True
    except Exception as exc:  # noqa: BLE001 - the view still shows the frame
        text = f"overlays could not be drawn: {type(exc).__name__}: {exc}"
        if not state.messages or state.messages[-1].text != text:
            state.notify(text, "error")
            print(f"lpv-explorer: {text}", file=sys.stderr)
        return texture, bottom_first


@dataclass(frozen=True)
class Hover:
    """What is under the mouse: a pixel of one side's frame or a cell of the slice."""

    side: str
    pixel: tuple[int, int]
    pick: PickInfo | None = None
    cell: CellInfo | None = None
    slice_value: tuple[str, float] | None = None
    """(what the slice shows, its value in the hovered cell) when hovering the slice."""


def hover_at(state: AppState, side: str, pixel: tuple[int, int]) -> Hover | None:
    """The slice cell seen at ``pixel`` when the slice is shown and in front of the
    surface there, else the pixel's surface."""
    result = side_result(state, side)
    if result is None or result.gbuffer_position is None:
        return None
    o = state.overlays
    if o.slice:
        try:
            _, spec, cascade, _ = Q.slice_source(result, o)
        except ValueError:
            spec = None
        if spec is not None:
            layer = Q.slice_layer(o, Q.layers_along(spec, o.slice_axis))
            cell = slice_hit(result, spec, o.slice_axis, layer, *pixel, on_top=o.slice_on_top)
            if cell is not None:
                compositor = state.runtime.services.compositor
                field = None if compositor is None else compositor.slice_field(side)
                value = None if field is None or field.spec != spec else (
                    field.label, float(field.values[cell]))
                return Hover(side, pixel, cell=pick_cell(result, cascade, *cell),
                             slice_value=value)
    return Hover(side, pixel, pick=pick_with_references(state, result, pixel, side))


def pick_with_references(state: AppState, result, pixel, side: str = "A"
                         ) -> PickInfo | None:
    """:func:`pick_pixel` with the reference radiance of every mode computed for this
    pixel of this frame (the Picked panel's button), its final colour exposed as
    ``side``'s display shows it (its exposure and indirect-only: the frame's own are the
    pipelines' pinned ones)."""
    from explorer.ui.overlays.pixel_reference import pixel_references

    pick = pick_pixel(result, *pixel)
    if pick is None or not pick.surface:
        return pick
    display = state.runtime.frame.displays.get(side)
    if display is not None:
        pick = replace(pick, final=np.asarray(result.final_pixel(
            pick.y, pick.x, display.exposure, display.indirect_only), np.float64))
    found = pixel_references(state).values(result, pixel)
    return replace(pick, references=found) if found else pick


def set_picked(state: AppState, hover: Hover) -> None:
    """Make ``hover`` the picked point: the surface point under a pixel (with the finest
    cascade holding it), or the centre of a slice cell."""
    o = state.overlays
    if hover.cell is not None:
        o.pick("cell", hover.side, hover.cell.cascade, hover.cell.centre)
    elif hover.pick is not None and hover.pick.surface:
        cascade = hover.pick.cells[0].cascade if hover.pick.cells else 0
        o.pick("pixel", hover.side, cascade, hover.pick.position)


def over_image(state: AppState, draw, origin, end, hovered: bool,
               split_x: float | None) -> None:
    """Colour bar, tooltip, picking and slice wheel over the view image spanning
    ``origin``..``end`` (screen units); ``split_x``: the divider of the split view."""
    rt, o = state.runtime, state.overlays
    if o.slice and rt.services.compositor is not None:
        # one bar per side: each side's automatic scale is its own
        sides = ("A",) if split_x is None else ("A", "B")
        for side in sides:
            field = rt.services.compositor.slice_field(side)
            if field is not None:
                at_left = side == "A" and split_x is not None
                _colour_bar(draw, field, origin, end, at_left)
                if side == "A":
                    _caption(draw, field.label, origin, end)
    draw_marks(draw, rt.frame.result, step_marks(state), origin, end)
    delta = imgui.get_io().mouse_delta
    if hovered and (delta.x or delta.y):
        rt.view.pointer_moved = True
    # A pointer that never moved (a scripted run under Xvfb, where it rests mid-screen) is
    # nobody's: no tooltip in screenshots.
    if not hovered or rt.view.view_rect is None or not rt.view.pointer_moved:
        rt.view.hover = None
        return
    mouse = imgui.get_mouse_pos()
    side = "B" if split_x is not None and mouse.x >= split_x else "A"
    result = side_result(state, side)
    scale = imgui.get_io().display_framebuffer_scale.x or 1.0
    pixel = None
    if result is not None:
        height, width = result.image_size
        pixel = view_pixel(rt.view.view_rect, (mouse.x * scale, mouse.y * scale), (width, height))
    rt.view.hover = None if pixel is None else hover_at(state, side, pixel)
    _slice_wheel(state)
    near_divider = split_x is not None and abs(mouse.x - split_x) < 8.0
    if imgui.is_mouse_clicked(0):
        rt.view.view_press = (mouse.x, mouse.y)
    if imgui.is_mouse_released(0) and rt.view.view_press is not None:
        dx, dy = mouse.x - rt.view.view_press[0], mouse.y - rt.view.view_press[1]
        rt.view.view_press = None
        if dx * dx + dy * dy <= CLICK_SLOP ** 2 and rt.view.hover is not None and not near_divider:
            set_picked(state, rt.view.hover)
    if rt.view.hover is not None and not imgui.is_mouse_down(0):
        _tooltip(rt.view.hover)


def step_marks(state: AppState) -> tuple:
    """The marks of the lesson step on screen (explorer/lessons/marks.py): none when no
    lesson step is applied or the reader changed what the step shows."""
    from explorer.ui.lesson_panel import shows_step

    session = getattr(state, "lesson_session", None)   # none made here: no lesson, no marks
    step = session.step if session is not None and session.applied else None
    if step is None or not step.marks or not shows_step(state.settings, step):
        return ()
    return step.marks


def _slice_wheel(state: AppState) -> None:
    """ctrl + wheel (or [ and ]) moves the slice by one layer."""
    o, io = state.overlays, imgui.get_io()
    step = 0
    if io.key_ctrl and io.mouse_wheel != 0.0:
        step = 1 if io.mouse_wheel > 0 else -1
    elif imgui.is_key_pressed(imgui.Key.right_bracket):
        step = 1
    elif imgui.is_key_pressed(imgui.Key.left_bracket):
        step = -1
    result = state.runtime.frame.result
    if step and o.slice and result is not None:
        n = Q.layers_along(result.grid_spec, o.slice_axis)
        o.slice_index = min(max(Q.slice_layer(o, n) + step, 0), n - 1)


def _tooltip(hover: Hover) -> None:
    rows = cell_rows(hover.cell, 3) if hover.cell is not None else (
        _pixel_tooltip_rows(hover.pick) if hover.pick is not None else [])
    if not rows:
        return
    imgui.begin_tooltip()
    imgui.text_disabled(f"side {hover.side} · click to pick")
    if hover.slice_value is not None:
        label, value = hover.slice_value
        imgui.text(f"{label}: {value:.4g} (mean of r, g, b)")
    if imgui.begin_table("##hover", 2):
        for label, value in rows:
            imgui.table_next_row()
            imgui.table_next_column()
            imgui.text_disabled(label)
            imgui.table_next_column()
            imgui.text(value)
        imgui.end_table()
    imgui.end_tooltip()


def _pixel_tooltip_rows(pick: PickInfo) -> list[tuple[str, str]]:
    """The first rows of the pixel (position to final) and, once computed, its reference
    radiance with the ratio LPV / reference."""
    rows = pixel_rows(pick, 3)
    shown = rows[:8]
    shown += [row for row in rows[8:] if row[0].startswith(("reference", "indirect / ref"))]
    return shown


def _colour_bar(draw, field: Q.SliceField, origin, end, at_left: bool) -> None:
    from explorer.ui.widgets import scale_bar

    height = min(end.y - origin.y - 90.0, 260.0)
    if height < 40:
        return
    x = origin.x + 12.0 if at_left else end.x - _BAR_ROOM
    y = origin.y + 48.0
    backdrop = imgui.get_color_u32(imgui.ImVec4(0.0, 0.0, 0.0, 0.55))
    draw.add_rect_filled((x - 6, y - 8), (x + _BAR_ROOM - 8, y + height + 12), backdrop, 4.0)
    scale_bar(draw, imgui.ImVec2(x, y), height, field.high,
              signed=field.colour_map == "diverging", value_at=field.value_at)


def _caption(draw, text: str, origin, end) -> None:
    """What the slice shows, above the view's hint line."""
    line = imgui.get_text_line_height()
    pos = imgui.ImVec2(origin.x + 6, end.y - 2 * line - 16)
    size = imgui.calc_text_size(text)
    draw.add_rect_filled((pos.x - 2, pos.y - 3), (pos.x + size.x + 8, pos.y + size.y + 3),
                         imgui.get_color_u32(imgui.ImVec4(0.0, 0.0, 0.0, 0.6)), 3.0)
    draw.add_text((pos.x + 3, pos.y), imgui.get_color_u32(imgui.ImVec4(1, 1, 1, 0.95)), text)


def draw_marks(draw, result, marks, origin, end) -> None:
    """The step's marks and their labels, placed on ``result``'s picture drawn between
    ``origin`` and ``end`` (screen corners); nothing without marks or a frame."""
    if not marks or result is None:
        return
    from explorer.ui.overlays import marks as mark_overlay

    def text_size(label: str) -> tuple[float, float]:
        size = imgui.calc_text_size(label)
        return size.x, size.y

    mark_overlay.draw(draw, mark_overlay.placements(
        result, marks, (origin.x, origin.y), (end.x, end.y), text_size))
