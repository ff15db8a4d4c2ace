"""Per-cell glyphs of an SH grid slice, drawn with an imgui draw list over its picture.

A lobe glyph is the polar curve of the radiant intensity (mean of the colour channels)
toward the directions of the slice plane; an arrow glyph points along the band-1 part of
the cell's SH, the direction light in the cell is mostly heading. Both are scaled by the
largest value in the slice (or a given ``peak``), so the strongest cell fills its square.

The slice is ``grid[:, :, :, z]`` shown with x to the right and y up: cell (x, y) sits in
column x and row ``N − 1 − y`` of the picture (as :func:`explorer.ui.images.grid_slice`).
"""

from __future__ import annotations

import numpy as np
from imgui_bundle import imgui

from explorer.lpv import constants as K
from explorer.lpv.twin.light_grid import grid_sh_order, sh_basis

SAMPLES = 32
_MIN_PIXELS = 0.6       # a glyph smaller than this is not drawn


def slice_directions(samples: int = SAMPLES) -> np.ndarray:
    """(samples, 3) unit directions around the slice plane (z = 0)."""
    angles = np.linspace(0.0, 2.0 * np.pi, samples, endpoint=False)
    return np.stack([np.cos(angles), np.sin(angles), np.zeros_like(angles)], axis=1)


def slice_intensity(grid: np.ndarray, z: int, samples: int = SAMPLES) -> np.ndarray:
    """(N, N, samples) intensity of cell (x, y) of slice ``z`` toward each slice direction
    (mean of the colour channels; signed)."""
    grid = np.asarray(grid, np.float64)
    coeffs = grid[:, :, :, z, :].mean(axis=0)                       # (x, y, k)
    basis = sh_basis(slice_directions(samples), grid_sh_order(grid))  # (samples, k)
    return coeffs @ basis.T


def _cell_centre(pos, size, n: int, x: int, y: int) -> tuple[float, float, float]:
    cell_w, cell_h = size.x / n, size.y / n
    return (pos.x + (x + 0.5) * cell_w, pos.y + (n - 1 - y + 0.5) * cell_h,
            0.5 * min(cell_w, cell_h))


def draw_lobe_glyphs(draw: imgui.ImDrawList, grid: np.ndarray, z: int, pos, size,
                     colour: int, negative_colour: int | None = None,
                     peak: float | None = None) -> None:
    """Polar intensity curves per cell; with ``negative_colour`` the negative part of a
    lobe is drawn too (as |value|, in that colour), else it is clamped away."""
    n = grid.shape[1]
    values = slice_intensity(grid, z)
    dirs = slice_directions()
    if peak is not None:
        top = peak
    else:
        top = float(np.abs(values).max() if negative_colour is not None else values.max())
    if top <= 0.0:
        return
    for sign, tint in ((1.0, colour), (-1.0, negative_colour)):
        if tint is None:
            continue
        radius = np.maximum(sign * values, 0.0) / top
        for x in range(n):
            for y in range(n):
                cx, cy, half = _cell_centre(pos, size, n, x, y)
                r = radius[x, y] * half
                if r.max() < _MIN_PIXELS:
                    continue
                points = [imgui.ImVec2(cx + r[i] * dirs[i, 0], cy - r[i] * dirs[i, 1])
                          for i in range(len(dirs))]
                draw.add_polyline(points, tint, 1.0, imgui.ImDrawFlags_.closed)


def band1_vectors(grid: np.ndarray, z: int) -> np.ndarray:
    """(N, N, 2) in-plane (x, y) band-1 vector per cell, mean of the channels: the SH
    I(ω) = c0·f0 + c1·(−f1·ω_y + f2·ω_z − f3·ω_x) grows fastest along (−f3, −f1, f2)
    (docs/MODEL.md basis), scaled by c1 to intensity units."""
    coeffs = np.asarray(grid, np.float64)[:, :, :, z, :4].mean(axis=0)
    return K.SH_C1 * np.stack([-coeffs[..., 3], -coeffs[..., 1]], axis=-1)


def draw_arrow_glyphs(draw: imgui.ImDrawList, grid: np.ndarray, z: int, pos, size,
                      colour: int, peak: float | None = None) -> None:
    """An arrow per cell along its band-1 vector, length relative to the slice's longest."""
    n = grid.shape[1]
    vectors = band1_vectors(grid, z)
    lengths = np.linalg.norm(vectors, axis=-1)
    top = peak if peak is not None else float(lengths.max())
    if top <= 0.0:
        return
    for x in range(n):
        for y in range(n):
            cx, cy, half = _cell_centre(pos, size, n, x, y)
            length = lengths[x, y] / top * half * 0.9
            if length < _MIN_PIXELS * 2:
                continue
            ux, uy = vectors[x, y] / lengths[x, y]
            tip = imgui.ImVec2(cx + ux * length, cy - uy * length)
            tail = imgui.ImVec2(cx - ux * length, cy + uy * length)
            draw.add_line(tail, tip, colour, 1.5)
            head = min(0.45 * length, 6.0)
            left = imgui.ImVec2(tip.x - head * (ux + 0.5 * uy), tip.y + head * (uy - 0.5 * ux))
            right = imgui.ImVec2(tip.x - head * (ux - 0.5 * uy), tip.y + head * (uy + 0.5 * ux))
            draw.add_triangle_filled(tip, left, right, colour)
