"""What the in-scene overlays draw, computed from FrameResult arrays (pure numpy, no GL).

The renderers in this package only upload what these functions return, so every colour
and size on screen can be checked against the arrays here. Scalars are the mean of the
three colour channels (the slice is one colour map, not an RGB image).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from explorer.lpv import constants as C
from explorer.lpv.grid import GridSpec
from explorer.lpv.twin.light_grid import sh_basis
from explorer.ui.images import direction_from_angles
from explorer.ui.state import SLICE_AXES, OverlayState
from explorer.ui.textures import diverging, heat, robust_max

GLYPH_TARGET_COUNT = 16
"""The automatic glyph stride keeps about this many glyphs along each side of the slice."""
PICKED_NEIGHBOURHOOD = 1
"""Glyph mode "picked": the picked cell and the cells up to this many steps away."""
COLOUR_MAP_SIZE = 256
PERCENTILE_CELLS = 1000
"""Cells holding light from which on the automatic colour scale is a percentile."""
LOG_DECADES = 3.0
"""A logarithmic slice spans this many decades below the top of its scale."""


# ------------------------------------------------------------------------- the slice
@dataclass(frozen=True)
class SliceField:
    """A scalar per cell of one grid and how to colour it.

    ``values`` (N, N, N) in the grid's (x, y, z) order; ``low``/``high`` the values at the
    bottom and top of the colour bar; ``colour_map`` "heat" or "diverging"; ``label`` what
    the values are, with units; ``spec`` the grid they live on; ``log``: the heat map runs
    over log10 of the values, ``low = high·10^−LOG_DECADES`` (values ≤ low are black)."""

    values: np.ndarray
    low: float
    high: float
    colour_map: str
    label: str
    spec: GridSpec
    cascade: int
    log: bool = False

    def position(self, values) -> np.ndarray:
        """Where ``values`` fall on the colour bar, 0 (bottom) .. 1 (top)."""
        values = np.asarray(values, np.float64)
        if self.log:
            ratio = np.maximum(values, 1e-300) / self.high
            return np.clip(np.log10(ratio) / LOG_DECADES + 1.0, 0.0, 1.0)
        span = max(self.high - self.low, 1e-30)
        return np.clip((values - self.low) / span, 0.0, 1.0)

    def value_at(self, position: float) -> float:
        """The value at ``position`` (0 .. 1) of the colour bar (the bar's labels)."""
        if self.log:
            return self.high * 10.0 ** (LOG_DECADES * (position - 1.0))
        return self.low + (self.high - self.low) * position


SIGNED_QUANTITIES = tuple(f"sh{k}" for k in range(1, 9))


def resolved_colour_map(overlays: OverlayState) -> str:
    if overlays.colour_map != "auto":
        return overlays.colour_map
    return "diverging" if overlays.slice_quantity in SIGNED_QUANTITIES else "heat"


def slice_source(result, overlays: OverlayState) -> tuple[np.ndarray, GridSpec, int, str]:
    """(grid (3, N, N, N, C), its GridSpec, its cascade, its name in words) the slice reads.
    "in-flight" reads grid_t of the finest cascade (the only one whose steps are kept);
    a ValueError when the steps are not recorded yet or the coefficient does not exist."""
    if overlays.slice_quantity == "in-flight":
        if not result.steps:
            raise ValueError("the propagation steps are not recorded yet")
        t = int(np.clip(overlays.slice_step, 0, len(result.steps) - 1))
        return result.steps[t], result.grid_spec, 0, grid_words(step=t)
    grids = result.cascade_accumulated or [result.accumulated]
    specs = result.cascade_specs or [result.grid_spec]
    k = int(np.clip(overlays.cascade, 0, len(grids) - 1))
    return grids[k], specs[k], k, grid_words(cascade=k, cascades=len(grids))


def grid_words(step: int | None = None, cascade: int = 0, cascades: int = 1) -> str:
    """A grid named in words for the learner (captions, hovers, the Inspect panel): the
    light in flight after ``step`` (grid_t of docs/MODEL.md), else the accumulated light
    (acc_N) of ``cascade`` when there are several."""
    if step is not None:
        return "injected light (step 0)" if step == 0 else f"light in flight after step {step}"
    return "accumulated light" if cascades <= 1 else f"accumulated light, cascade {cascade}"


def quantity_field(grid: np.ndarray, quantity: str, direction=None) -> np.ndarray:
    """(N, N, N) mean over the colour channels of ``quantity`` (state.SLICE_QUANTITIES).

    intensity: ⟨f, Y(ω)⟩ toward the unit ``direction`` [W/sr] (not clamped: negative
    values are SH ringing); flux, in-flight: 2√π·c0 [W] (docs/MODEL.md, flux of a cell);
    sh<k>: coefficient k."""
    grid = np.asarray(grid, np.float64)
    coefficients = grid.shape[-1]
    if quantity == "intensity":
        order = 2 if coefficients == 9 else 1
        towards = np.asarray(direction if direction is not None else (0.0, 1.0, 0.0),
                             np.float64)
        basis = sh_basis(towards / np.linalg.norm(towards), order)
        return np.einsum("cxyzk,k->xyz", grid, basis) / grid.shape[0]
    if quantity in ("flux", "in-flight"):
        return C.SH_FLUX_FACTOR * grid[..., 0].mean(axis=0)
    if quantity.startswith("sh") and quantity[2:].isdigit():
        k = int(quantity[2:])
        if k >= coefficients:
            raise ValueError(f"{quantity} needs sh_order 2; this grid holds {coefficients} "
                             "coefficients per cell")
        return grid[..., k].mean(axis=0)
    raise ValueError(f"unknown slice quantity {quantity!r}")


def slice_field(result, overlays: OverlayState, top: float | None = None) -> SliceField:
    """The slice's scalar field with its colour scale (automatic: the robust maximum over
    the whole grid, so moving the slice keeps the colours comparable; ``top``: another
    side's automatic top, for one scale across a comparison)."""
    grid, spec, cascade, name = slice_source(result, overlays)
    direction = direction_from_angles(overlays.direction_azimuth, overlays.direction_elevation)
    values = quantity_field(grid, overlays.slice_quantity, direction)
    colour_map = resolved_colour_map(overlays)
    if overlays.slice_scale > 0:
        top = overlays.slice_scale
    elif top is None:
        top = automatic_top(np.abs(values) if colour_map == "diverging" else values)
    log = overlays.slice_log and colour_map == "heat"
    low = -top if colour_map == "diverging" else (top * 10.0 ** -LOG_DECADES if log else 0.0)
    return SliceField(values.astype(np.float32), float(low), float(top), colour_map,
                      _label(overlays, name, direction), spec, cascade, log)


def automatic_top(values: np.ndarray) -> float:
    """The top of an automatic colour scale, taken over the cells that hold anything: the
    robust maximum (a few extreme cells beside a wall do not wash the slice out), or the
    maximum when fewer than :data:`PERCENTILE_CELLS` cells hold light. In its first steps
    light fills a few cells around its source; over all cells a percentile would fall
    inside those few, and over a few hundred it would still saturate the brightest ones,
    which are the light the slice is there to show."""
    values = np.asarray(values)
    holding = values[values != 0]
    if holding.size == 0:
        return robust_max(values)
    if holding.size < PERCENTILE_CELLS:
        return float(max(holding.max(), 1e-12))
    return robust_max(holding)


def _label(overlays: OverlayState, name: str, direction: np.ndarray) -> str:
    quantity = overlays.slice_quantity
    if quantity == "intensity":
        d = ", ".join(f"{v:+.2f}" for v in direction)
        return f"{name}: intensity toward ({d}) [W/sr]"
    if quantity in ("flux", "in-flight"):
        return f"{name}: flux per cell [W]"
    return f"{name}: SH coefficient {quantity[2:]} [W/sr]"


def layers_along(spec: GridSpec, axis: str) -> int:
    """Cell layers of ``spec`` along the slice axis ``axis`` (x, y or z)."""
    return int(spec.cells[SLICE_AXES.index(axis)])


def slice_layer(overlays: OverlayState, resolution: int) -> int:
    """The cell layer the slice cuts (slice_index −1: the middle one), clamped."""
    index = overlays.slice_index if overlays.slice_index >= 0 else resolution // 2
    return int(np.clip(index, 0, resolution - 1))


def plane_axes(axis: str) -> tuple[int, int, int]:
    """(normal axis, u axis, v axis) of the slice plane; u < v are the other two axes."""
    a = SLICE_AXES.index(axis)
    u, v = (i for i in range(3) if i != a)
    return a, u, v


def slice_values(values: np.ndarray, axis: str, layer: int) -> np.ndarray:
    """(N_u, N_v) values of one cell layer: ``out[i, j]`` is the cell with coordinate i on
    the plane's u axis and j on its v axis (plane_axes)."""
    return np.ascontiguousarray(np.take(values, layer, axis=SLICE_AXES.index(axis)))


def plane_corners(spec: GridSpec, axis: str, layer: int) -> tuple[np.ndarray, np.ndarray,
                                                                  np.ndarray]:
    """(corner, u edge, v edge) of the slice quad: the plane through the centres of the
    cells of ``layer``, spanning the whole grid along the other two axes."""
    a, u, v = plane_axes(axis)
    corner = np.asarray(spec.origin, np.float64).copy()
    corner[a] += (layer + 0.5) * spec.cell_size
    edge_u, edge_v = np.zeros(3), np.zeros(3)
    edge_u[u], edge_v[v] = spec.extents[u], spec.extents[v]
    return corner, edge_u, edge_v


def colour_table(name: str, size: int = COLOUR_MAP_SIZE) -> np.ndarray:
    """(size, 3) float32 colours of a colour map from its bottom to its top: the same
    functions the colour bar (widgets.scale_bar) draws with."""
    t = np.linspace(0.0, 1.0, size)
    if name == "diverging":
        return diverging(2.0 * t - 1.0, 1.0).astype(np.float32)
    if name == "heat":
        return heat(t).astype(np.float32)
    raise ValueError(f"unknown colour map {name!r}; use 'heat' or 'diverging'")


def map_colours(values: np.ndarray, field: SliceField) -> np.ndarray:
    """(..., 3) colours of ``values`` as the slice shader shows them (nearest entry of the
    colour table)."""
    t = field.position(values)
    table = colour_table(field.colour_map)
    return table[np.rint(t * (len(table) - 1)).astype(np.int64)]


# ------------------------------------------------------------------------- SH glyphs
def glyph_directions(rings: int = 8, segments: int = 16) -> tuple[np.ndarray, np.ndarray]:
    """A UV sphere of unit directions and its triangle indices: the glyph mesh."""
    theta = np.linspace(0.0, math.pi, rings + 1)
    phi = np.linspace(0.0, 2.0 * math.pi, segments + 1)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    dirs = np.stack([np.sin(t) * np.cos(p), np.cos(t), np.sin(t) * np.sin(p)], -1)
    dirs = dirs.reshape(-1, 3)
    quads = []
    for r in range(rings):
        for s in range(segments):
            a, b = r * (segments + 1) + s, (r + 1) * (segments + 1) + s
            quads += [a, b, a + 1, a + 1, b, b + 1]
    return dirs.astype(np.float32), np.asarray(quads, np.int32)


@dataclass(frozen=True)
class Glyphs:
    """Instances of the SH glyph mesh: ``centres`` (G, 3), ``coefficients`` (G, 9) (the
    channel mean, zero-padded for L1), ``scales`` (G,) world units per W/sr, ``spacing``
    the distance between neighbouring glyphs, ``stride`` the cells per glyph step."""

    centres: np.ndarray
    coefficients: np.ndarray
    scales: np.ndarray
    spacing: float
    stride: int


def auto_glyph_stride(resolution: int) -> int:
    """Cells per glyph step that keep about GLYPH_TARGET_COUNT glyphs along a side."""
    return max(1, math.ceil(resolution / GLYPH_TARGET_COUNT))


def glyph_stride(overlays: OverlayState, resolution: int) -> int:
    return overlays.glyph_stride if overlays.glyph_stride > 0 else auto_glyph_stride(resolution)


def glyph_cells(overlays: OverlayState, spec: GridSpec) -> tuple[np.ndarray, int]:
    """(cell indices (G, 3), stride) of the glyphs: every ``stride``-th cell of the slice
    layer (the middle cell of each stride block), or the cell holding the picked point and
    its neighbours."""
    cells_per_axis = np.asarray(spec.cells)
    if overlays.glyph_cells == "picked":
        point = overlays.picked_point
        if point is None:
            return np.zeros((0, 3), np.int64), 1
        centre = spec.cell_index(np.asarray(point))
        r = PICKED_NEIGHBOURHOOD
        offsets = np.stack(np.meshgrid(*[np.arange(-r, r + 1)] * 3, indexing="ij"),
                           -1).reshape(-1, 3)
        cells = centre + offsets
        return cells[np.all((cells >= 0) & (cells < cells_per_axis), axis=1)], 1
    stride = glyph_stride(overlays, int(cells_per_axis.max()))
    a, u, v = plane_axes(overlays.slice_axis)
    iu, iv = np.meshgrid(np.arange(stride // 2, cells_per_axis[u], stride),
                         np.arange(stride // 2, cells_per_axis[v], stride), indexing="ij")
    cells = np.zeros((iu.size, 3), np.int64)
    cells[:, a] = slice_layer(overlays, int(cells_per_axis[a]))
    cells[:, u], cells[:, v] = iu.ravel(), iv.ravel()
    return cells, stride


def glyph_source(result, overlays: OverlayState) -> tuple[np.ndarray, GridSpec]:
    """The grid the glyphs show: the slice's (acc_N or grid_t) on the slice, acc_N of the
    picked cell's cascade around the picked cell."""
    if overlays.glyph_cells == "picked":
        grids = result.cascade_accumulated or [result.accumulated]
        specs = result.cascade_specs or [result.grid_spec]
        k = int(np.clip(overlays.picked_cascade, 0, len(grids) - 1))
        return grids[k], specs[k]
    grid, spec, _, _ = slice_source(result, overlays)
    return grid, spec


def glyphs(result, overlays: OverlayState) -> Glyphs:
    """The glyph instances: lobe radius |f(ω)| (mean channel intensity) times a per-glyph
    scale, so that the largest lobe drawn reaches ``glyph_scale`` × half the glyph
    spacing whatever the grid size, and a glyph whose peak is p reaches that times
    p/p_max ("linear"), √(p/p_max) ("sqrt") or 1 ("equal")."""
    grid, spec = glyph_source(result, overlays)
    cells, stride = glyph_cells(overlays, spec)
    grid = np.asarray(grid, np.float64)
    coefficients = np.zeros((len(cells), 9))
    if len(cells):
        ix, iy, iz = cells.T
        mean = grid[:, ix, iy, iz, :].mean(axis=0)
        coefficients[:, :mean.shape[1]] = mean
    directions, _ = glyph_directions()
    lobes = np.abs(coefficients @ sh_basis(directions.astype(np.float64), 2).T)  # (G, D)
    peaks = lobes.max(axis=1) if len(cells) else np.zeros(0)
    spacing = stride * spec.cell_size
    reach = 0.5 * spacing * overlays.glyph_scale
    top = float(peaks.max()) if len(peaks) else 0.0
    relative = peaks / top if top > 0 else np.zeros_like(peaks)
    size = {"linear": relative, "sqrt": np.sqrt(relative),
            "equal": np.ones_like(relative)}[overlays.glyph_sizing]
    # the drawn peak is scale·p = reach·size
    scales = np.divide(reach * size, peaks, out=np.zeros_like(peaks), where=peaks > 0)
    centres = spec.cell_centre(cells) if len(cells) else np.zeros((0, 3))
    keep = peaks > 0
    return Glyphs(centres[keep].astype(np.float32), coefficients[keep].astype(np.float32),
                  scales[keep].astype(np.float32), spacing, stride)


GLYPH_AXIS_COLOUR = (1.0, 1.0, 1.0, 1.0)
AXIS_MIN_SPACING = 0.04
"""An axis whose part outside its lobe is shorter than this fraction of the glyph spacing
is not drawn: the lobe is too round to have a direction worth an arrow."""
AXIS_REACH = 1.6
"""How far an axis reaches past its lobe, in units of the lobe's lean ``scale·|b|``."""
AXIS_HEAD = 0.5
"""The arrow head's length over the length of the axis outside the lobe."""


def band1_direction(coefficients: np.ndarray) -> np.ndarray:
    """(G, 3) band-1 vector b of each glyph's SH in world axes: with the basis of
    docs/MODEL.md, f(ω) = c0·Y0 + C1·(−f1·ω_y + f2·ω_z − f3·ω_x) = c0·Y0 + b·ω with
    b = C1·(−f3, −f1, f2), so f is largest along b and |b| is how much it leans."""
    c = np.asarray(coefficients, np.float64)
    return C.SH_C1 * np.stack([-c[:, 3], -c[:, 1], c[:, 2]], axis=1)


def glyph_axes(glyphs: Glyphs) -> tuple[np.ndarray, np.ndarray]:
    """(segments (K, 2, 3), colours (K, 4)) of an arrow per glyph that holds light (c0 > 0)
    along its band-1 vector b: from the cell centre through the lobe's surface at
    ``scale·f(b̂)`` and :data:`AXIS_REACH` ``·scale·|b|`` beyond it, so that the part
    outside the lobe, and the head on it, grow with how much the lobe leans (a round lobe
    gets none). Drawn over the glyphs, it tells the lobe's axis from any camera, also
    head-on (the head's four strokes then form a cross)."""
    b = band1_direction(glyphs.coefficients)
    length = np.linalg.norm(b, axis=1)
    keep = (np.asarray(glyphs.coefficients[:, 0], np.float64) > 0) & (length > 0)
    scales = np.asarray(glyphs.scales, np.float64)
    poke = AXIS_REACH * scales * length
    keep &= poke >= AXIS_MIN_SPACING * glyphs.spacing
    if not keep.any():
        return np.zeros((0, 2, 3)), np.zeros((0, 4))
    axis = b[keep] / length[keep, None]
    at_axis = np.einsum("gk,gk->g", np.asarray(glyphs.coefficients, np.float64)[keep],
                        sh_basis(axis, 2))
    centre = np.asarray(glyphs.centres, np.float64)[keep]
    tip = centre + axis * (scales[keep] * np.abs(at_axis) + poke[keep])[:, None]
    head = AXIS_HEAD * poke[keep]
    # two unit vectors across the axis for the head's strokes
    helper = np.where(np.abs(axis[:, 1:2]) < 0.9, [[0.0, 1.0, 0.0]], [[1.0, 0.0, 0.0]])
    across = np.cross(axis, helper)
    across /= np.linalg.norm(across, axis=1, keepdims=True)
    other = np.cross(axis, across)
    base = tip - axis * head[:, None]
    segments = [np.stack([centre, tip], axis=1)]
    for side in (across, -across, other, -other):
        segments.append(np.stack([tip, base + 0.5 * head[:, None] * side], axis=1))
    segments = np.concatenate(segments)
    return segments, np.tile(GLYPH_AXIS_COLOUR, (len(segments), 1))


# ------------------------------------------------------------------------- splats
@dataclass(frozen=True)
class Splats:
    """Oriented discs: ``positions``, ``normals``, ``colours`` (M, 3), ``radii`` (M,)."""

    positions: np.ndarray
    normals: np.ndarray
    colours: np.ndarray
    radii: np.ndarray

    @property
    def count(self) -> int:
        return len(self.radii)

    def packed(self) -> np.ndarray:
        """(M, 10) float32 rows: position, normal, colour, radius (the instance buffer)."""
        return np.ascontiguousarray(np.concatenate(
            [self.positions, self.normals, self.colours, self.radii[:, None]], axis=1),
            np.float32)


def vpl_order(count: int) -> np.ndarray:
    """A fixed pseudo-random order of the VPLs: drawing its first ``density·M`` entries
    shows an even subset that grows without flicker as the density rises."""
    return np.random.default_rng(0).permutation(count)


def vpl_splats(vpls, max_radius: float) -> Splats:
    """Every VPL as a disc of its surfel's area (radius √(A/π), A = texel_area·depth²,
    docs/MODEL.md "Injection"), at most ``max_radius``, along its normal, coloured by its
    flux normalised to the robust maximum of the brightest channel and brightened with a
    square root. Rows in :func:`vpl_order` (draw a prefix to thin them out)."""
    count = vpls.count
    order = vpl_order(count)
    flux = np.asarray(vpls.flux, np.float64)[order]
    top = robust_max(flux.max(axis=1)) if count else 1.0
    colours = np.sqrt(np.clip(flux / top, 0.0, 1.0))
    radii = np.sqrt(vpls.surfel_area(squared=True)[order] / math.pi)
    return Splats(np.asarray(vpls.positions, np.float32)[order],
                  np.asarray(vpls.normals, np.float32)[order],
                  colours.astype(np.float32),
                  np.minimum(radii, max_radius).astype(np.float32))


BLOCKER_COLOUR = (0.78, 0.70, 1.0)
_ORIENTED = 0.1
"""A blocker whose band 1 is under this fraction of its band 0 has no orientation (a
double-sided surfel, or surfels facing opposite ways): its disc faces the camera."""


def blocker_splats(volume: np.ndarray, spec: GridSpec, mode: str, view_direction,
                   threshold: float = 1e-3) -> Splats:
    """The geometry volume's blockers (docs/MODEL.md "Geometry volume") as discs on the
    light grid's corners: area A = c0/(C_L0·sides)·h² (the surfels' area in the cell,
    sides 2 for double-sided), normal from band 1 (lobe(n) = (C_L0, −C_L1 n_y, C_L1 n_z,
    −C_L1 n_x)·A/h²). Corners whose area is under ``threshold`` of a cell face are left
    out."""
    volume = np.asarray(volume, np.float64)
    sides = 2.0 if mode == "double-sided" else 1.0
    area = volume[..., 0] / (C.SH_COSLOBE_C0 * sides)          # in cell faces
    corners = np.argwhere(area > threshold)
    if len(corners) == 0:
        empty = np.zeros((0, 3), np.float32)
        return Splats(empty, empty, empty, np.zeros(0, np.float32))
    ix, iy, iz = corners.T
    c = volume[ix, iy, iz]
    normals = np.stack([-c[:, 3], -c[:, 1], c[:, 2]], axis=1) / C.SH_COSLOBE_C1
    length = np.linalg.norm(normals, axis=1)
    oriented = length > _ORIENTED * area[ix, iy, iz] * sides
    facing = -np.asarray(view_direction, np.float64)
    normals = np.where(oriented[:, None], normals / np.maximum(length, 1e-30)[:, None],
                       facing / np.linalg.norm(facing))
    positions = np.asarray(spec.origin) + corners * spec.cell_size
    radii = np.minimum(np.sqrt(area[ix, iy, iz] / math.pi), 0.5) * spec.cell_size
    colours = np.tile(np.asarray(BLOCKER_COLOUR, np.float32), (len(corners), 1))
    return Splats(positions.astype(np.float32), normals.astype(np.float32), colours,
                  radii.astype(np.float32))


# ------------------------------------------------------------------------- wireframes
def box_segments(lo, hi) -> np.ndarray:
    """(12, 2, 3) edges of the axis-aligned box [lo, hi]."""
    lo, hi = np.asarray(lo, np.float64), np.asarray(hi, np.float64)
    corners = np.array([[(hi if (n >> a) & 1 else lo)[a] for a in range(3)]
                        for n in range(8)])
    edges = [(n, n | (1 << a)) for n in range(8) for a in range(3) if not (n >> a) & 1]
    return np.stack([corners[[i, j]] for i, j in edges])


def grid_box(spec: GridSpec) -> np.ndarray:
    lo = np.asarray(spec.origin, np.float64)
    return box_segments(lo, lo + spec.extents)


def cell_box(spec: GridSpec, cell) -> np.ndarray:
    lo = np.asarray(spec.origin, np.float64) + np.asarray(cell, np.float64) * spec.cell_size
    return box_segments(lo, lo + spec.cell_size)


def lattice_segments(spec: GridSpec, axis: str, layer: int) -> np.ndarray:
    """(n_u + 1 + n_v + 1, 2, 3) cell borders on the slice plane (through the layer's
    centres)."""
    corner, edge_u, edge_v = plane_corners(spec, axis, layer)
    _, u, v = plane_axes(axis)
    n_u, n_v = spec.cells[u], spec.cells[v]
    along_v = [(corner + s * edge_u, corner + s * edge_u + edge_v)
               for s in np.arange(n_u + 1) / n_u]
    along_u = [(corner + s * edge_v, corner + s * edge_v + edge_u)
               for s in np.arange(n_v + 1) / n_v]
    return np.asarray(along_v + along_u, np.float64)
