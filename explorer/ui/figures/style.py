"""Colours, number formats and small drawing helpers every figure shares.

One colour means one thing across figures: the exact function is near-white, L1 blue,
L2 amber, anything negative red, what the reader drags yellow.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np
from imgui_bundle import imgui, implot

from explorer.ui.textures import heat
from explorer.ui.widgets import ACCENT, DIM, ERROR, WARN

EXACT = imgui.ImVec4(0.93, 0.93, 0.96, 1.0)
L1 = ACCENT
L2 = imgui.ImVec4(1.0, 0.68, 0.26, 1.0)
NEGATIVE = ERROR
HANDLE = imgui.ImVec4(1.0, 0.88, 0.30, 1.0)
SIDE_COLOURS = (ACCENT, imgui.ImVec4(1.0, 0.55, 0.35, 1.0))
"""Configuration A, B in the audit plots."""
TEXT = imgui.ImVec4(0.90, 0.91, 0.93, 1.0)
MUTED = DIM
NOTE = WARN
GAP = 8.0


def with_alpha(colour: imgui.ImVec4, alpha: float) -> imgui.ImVec4:
    return imgui.ImVec4(colour.x, colour.y, colour.z, alpha)


def u32(colour: imgui.ImVec4, alpha: float | None = None) -> int:
    return imgui.get_color_u32(colour if alpha is None else with_alpha(colour, alpha))


def num(value: float, fmt: str = ".3f") -> str:
    """``value`` formatted, with a true minus sign (U+2212) instead of a hyphen."""
    return format(value, fmt).replace("-", "\u2212")


def watts(value: float) -> str:
    """A flux in watts with 3 significant digits, plain notation when readable."""
    magnitude = abs(value)
    if value == 0.0:
        return "0 W"
    return num(value, ".3g" if 1e-3 <= magnitude < 1e4 else ".2e") + " W"


def percent(fraction: float, digits: int = 1) -> str:
    """``0.875`` -> ``"87.5 %"``; tiny shares keep two significant digits."""
    value = 100.0 * fraction
    if value != 0.0 and abs(value) < 10.0 ** -digits:
        return num(value, ".2g") + " %"
    return num(value, f".{digits}f") + " %"


def share_of(value: float, reference: float) -> str:
    """``value`` relative to ``reference`` in words: a percentage, or ``"3.2×"`` above
    twice the reference (accumulated flux counts every step)."""
    if reference == 0.0 or not math.isfinite(reference):
        return "–"
    ratio = value / reference
    return num(ratio, ".3g") + "×" if abs(ratio) >= 2.0 else percent(ratio)


def side_by_side(width: float, min_each: float) -> bool:
    """Whether two panels of at least ``min_each`` pixels fit next to each other."""
    return width >= 2.0 * min_each + GAP


def views(width: float, drawers: Sequence[Callable[[float], None]],
          min_each: float = 240.0) -> None:
    """Draw two views side by side when both fit ``min_each`` pixels, else one under the
    other; each drawer gets the width it may use."""
    if len(drawers) == 2 and side_by_side(width, min_each):
        each = (width - GAP) / 2.0
        left = imgui.get_cursor_pos_x()
        for index, drawer in enumerate(drawers):
            if index:     # at its own place, whatever the first view drew
                imgui.same_line()
                imgui.set_cursor_pos_x(left + index * (each + GAP))
            imgui.begin_group()
            # a view's title wraps at the view's edge instead of pushing its neighbour out
            # of the column (tests/ui/test_figures_fit.py)
            imgui.push_text_wrap_pos(left + index * (each + GAP) + each)
            drawer(each)
            imgui.pop_text_wrap_pos()
            imgui.end_group()
    else:
        for drawer in drawers:
            drawer(width)


def heat_cells(draw, pos, side: float, values: np.ndarray, top: float, reach: float,
               outline_alpha: float | None = None) -> None:
    """An n×n slice of ``values`` (index ``[x, y]``, y up) as heat-coloured cells filling
    the square of ``side`` pixels at screen position ``pos``: each value relative to
    ``top``, square-rooted so that the faint front of the light shows, up to ``reach`` of
    the colour map (short of its white end where white glyphs go on top);
    ``outline_alpha``: each cell's outline (None: none)."""
    n = values.shape[0]
    cell = side / n
    colours = heat(reach * np.sqrt(np.clip(values / top, 0.0, 1.0))) if top > 0 else \
        np.zeros((n, n, 3))
    outline = None if outline_alpha is None else u32(TEXT, outline_alpha)
    for x in range(n):
        for y in range(n):
            p0 = imgui.ImVec2(pos.x + x * cell, pos.y + (n - 1 - y) * cell)
            p1 = imgui.ImVec2(p0.x + cell, p0.y + cell)
            r, g, b = (float(c) for c in colours[x, y])
            draw.add_rect_filled(p0, p1, imgui.get_color_u32(imgui.ImVec4(r, g, b, 1.0)))
            if outline is not None:
                draw.add_rect(p0, p1, outline)


def square(width: float, most: float = 440.0) -> imgui.ImVec2:
    """A square plot as wide as ``width`` allows, at most ``most`` pixels."""
    side = min(width, most)
    return imgui.ImVec2(side, side)


def plot_size(width: float, aspect: float = 1.0, max_height: float = 420.0) -> imgui.ImVec2:
    return imgui.ImVec2(width, min(width * aspect, max_height))


def readout_table(table_id: str, header: Sequence[str], rows: Sequence[Sequence[str]],
                  width: float, colours: Sequence[imgui.ImVec4 | None] = ()) -> None:
    """A small table of numbers under a figure; ``colours`` tints each column's header
    (the curve it describes)."""
    flags = (imgui.TableFlags_.borders_inner_h | imgui.TableFlags_.sizing_stretch_prop
             | imgui.TableFlags_.no_host_extend_x)
    if not imgui.begin_table(table_id, len(header), flags, imgui.ImVec2(width, 0)):
        return
    for name in header:
        imgui.table_setup_column(name)
    imgui.table_next_row(imgui.TableRowFlags_.headers)
    for column, name in enumerate(header):
        imgui.table_set_column_index(column)
        colour = colours[column] if column < len(colours) and colours[column] else MUTED
        imgui.text_colored(colour, name)
    for row in rows:
        imgui.table_next_row()
        for column, cell in enumerate(row):
            imgui.table_set_column_index(column)
            if column == 0:
                imgui.text_colored(MUTED, cell)
            else:
                imgui.text(cell)
    imgui.end_table()


def line_spec(colour: imgui.ImVec4, weight: float = 2.0, marker: int | None = None,
              fill_alpha: float = 1.0) -> implot.Spec:
    spec = implot.Spec()
    spec.line_color = colour
    spec.fill_color = colour
    spec.fill_alpha = fill_alpha
    spec.line_weight = weight
    if marker is not None:
        spec.marker = marker
        spec.marker_size = 3.5
        spec.marker_fill_color = colour
        spec.marker_line_color = colour
    return spec


def fill_polygon_in_plot(xs, ys, colour: imgui.ImVec4, alpha: float) -> None:
    """Fill the polygon (plot coordinates) inside the current implot plot."""
    if len(xs) < 3:
        return
    implot.push_plot_clip_rect()
    points = [implot.plot_to_pixels(float(x), float(y)) for x, y in zip(xs, ys)]
    implot.get_plot_draw_list().add_concave_poly_filled(points, u32(colour, alpha))
    implot.pop_plot_clip_rect()


def to_implot3d(points) -> np.ndarray:
    """World (x, y, z) -> implot3d (x, −z, y), a rotation: implot3d draws its z axis up,
    and world y is up in every scene and slice."""
    points = np.asarray(points, np.float64)
    return np.stack([points[..., 0], -points[..., 2], points[..., 1]], -1)


def from_implot3d(points) -> np.ndarray:
    """The inverse of :func:`to_implot3d`."""
    points = np.asarray(points, np.float64)
    return np.stack([points[..., 0], points[..., 2], -points[..., 1]], -1)
