"""Reading values under the mouse: a pixel of the frame or a cell of the grid, computed
from FrameResult arrays only (pure numpy, no GL), so every number shown is one the
pipeline holds.

Pixels are ``(x, y)`` = (column, row from the top), the row order of FrameResult images.
Cells are ``(i, j, k)`` along (x, y, z) of one cascade's :class:`GridSpec`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from explorer.lpv import constants as C
from explorer.lpv.audit import CellAudit
from explorer.lpv.cascades import blend_weights
from explorer.lpv.twin.light_grid import gather
from explorer.ui.overlays.quantities import plane_axes

CellIndex = tuple[int, int, int]


@dataclass(frozen=True)
class CellInfo:
    """One cell of one cascade and what the pipeline holds for it.

    The per-cell audit (docs/MODEL.md "Energy audit", restricted to this cell): the flux
    2√π·c0 of acc_N and, when the propagation steps were kept (finest cascade), of every
    grid_t; acc_N = Σ_t grid_t holds per cell, so ``accumulated_from_steps`` equals
    ``flux`` to rounding. The border, clamp and occlusion terms of the cell are records
    on the GPU, read for the picked cell only (:func:`cell_audit`)."""

    cascade: int
    index: CellIndex
    centre: np.ndarray
    cell_size: float
    coefficients: np.ndarray
    """(3, C) SH coefficients of acc_N (rows r, g, b; C = 4 or 9)."""
    flux: np.ndarray
    """(3,) flux of acc_N in the cell [W]."""
    share: np.ndarray
    """(3,) the cell's part of its cascade's acc_N flux (0 where the total is 0)."""
    in_flight: np.ndarray | None = None
    """(T+1, 3) flux of grid_t in the cell, t = 0 (injected) .. T."""
    accumulated_from_steps: np.ndarray | None = None
    """(3,) Σ_t of ``in_flight``."""
    blocker_area: float | None = None
    """Mean over the cell's 8 corners of the geometry volume's surfel area, in cell faces
    (c0 / C_L0; double-sided surfels count twice), None when the volume is off."""

    @property
    def injected(self) -> np.ndarray | None:
        return None if self.in_flight is None else self.in_flight[0]


@dataclass(frozen=True)
class PickInfo:
    """One pixel of a frame: the surface under it and the light the pipeline computed."""

    x: int
    y: int
    surface: bool
    """False for background pixels (nothing below holds then but the radiance zeros)."""
    position: np.ndarray
    normal: np.ndarray
    pixel_area: float
    albedo: np.ndarray
    direct: np.ndarray
    indirect: np.ndarray
    final: np.ndarray
    reference: np.ndarray | None
    """Reference radiance of the pixel when a reference image was computed, else None."""
    cells: tuple[CellInfo, ...]
    """The cell holding the surface point in each cascade that contains it."""
    weights: np.ndarray
    """(K,) the final gather's cascade weights at the point (one cascade: [1])."""
    indirect_from_grid: np.ndarray | None
    """albedo/π · Σ_k W_k·E_k recomputed in numpy from the accumulated grids (trilinear
    lookup, docs/MODEL.md "Final gather"): what the gather shader should have written."""
    references: tuple[tuple[str, np.ndarray], ...] = ()
    """(mode, (3,) radiance) of the one-bounce reference at this pixel for each mode
    computed ("visible", "unoccluded"; explorer/ui/overlays/pixel_reference.py)."""


# ------------------------------------------------------------------------- cells
def _cascades(result) -> tuple[list, list]:
    grids = result.cascade_accumulated or [result.accumulated]
    specs = result.cascade_specs or [result.grid_spec]
    return grids, specs


def _cell_in_steps(steps, index: tuple[int, int, int]) -> np.ndarray:
    """``(steps, 3)`` float64: band 0 of cell ``index`` in every kept step (read from the
    steps' boxes without building whole steps when they are explorer.lpv.kept_steps')."""
    cell = getattr(steps, "cell", None)
    if cell is not None:
        return np.asarray(cell(index)[..., 0], np.float64)
    return np.array([np.asarray(step[(slice(None),) + index + (0,)], np.float64)
                     for step in steps])


def pick_cell(result, cascade: int, i: int, j: int, k: int) -> CellInfo | None:
    """The values of cell (i, j, k) of ``cascade``; None outside the grid."""
    grids, specs = _cascades(result)
    if not 0 <= cascade < len(grids):
        return None
    spec, grid = specs[cascade], grids[cascade]
    index = (int(i), int(j), int(k))
    if not spec.inside(np.array(index)):
        return None
    coefficients = np.asarray(grid[(slice(None),) + index], np.float64)
    flux = C.SH_FLUX_FACTOR * coefficients[:, 0]
    total = C.SH_FLUX_FACTOR * np.asarray(grid[..., 0], np.float64).reshape(3, -1).sum(1)
    share = np.divide(flux, total, out=np.zeros(3), where=total != 0)
    in_flight = summed = None
    if cascade == 0 and result.steps:
        in_flight = C.SH_FLUX_FACTOR * _cell_in_steps(result.steps, index)
        summed = in_flight.sum(axis=0)
    blocker = None
    volumes = getattr(result, "cascade_geometry", None) or [result.geometry_volume]
    volume = volumes[cascade] if cascade < len(volumes) else None
    if volume is not None:
        corners = np.asarray(volume)[i:i + 2, j:j + 2, k:k + 2, 0]
        blocker = float(corners.mean() / C.SH_COSLOBE_C0)
    return CellInfo(cascade, index, spec.cell_centre(np.array(index)), float(spec.cell_size),
                    coefficients, flux, share, in_flight, summed, blocker)


# ------------------------------------------------------------------------- pixels
def pick_pixel(result, x: int, y: int, reference: np.ndarray | None = None
               ) -> PickInfo | None:
    """The values of pixel (x, y) (row 0 at the top); None outside the image.
    ``reference``: an (H, W, 3) reference radiance image of the same frame, if any."""
    height, width = result.image_size
    if not (0 <= x < width and 0 <= y < height):
        return None
    x, y = int(x), int(y)
    position = np.asarray(result.gbuffer_position[y, x], np.float64)
    normal = np.asarray(result.gbuffer_normal[y, x], np.float64)
    surface = bool(position[3] > 0.5)
    albedo = np.asarray(result.albedo[y, x], np.float64)
    cells: list[CellInfo] = []
    grids, specs = _cascades(result)
    weights = np.zeros(len(specs))
    from_grid = None
    if surface:
        p, n = position[:3], normal[:3]
        for cascade, spec in enumerate(specs):
            index = spec.cell_index(p)
            if spec.inside(index):
                cells.append(pick_cell(result, cascade, *index))
        weights = blend_weights(specs, p[None])[0]
        damping = bool(result.settings.gather_damping)
        # the net-flux gather adds the surface's own exitance a·E_direct = π·direct
        exitance = (math.pi * np.asarray(result.direct[y, x], np.float64)[None, :3]
                    if result.settings.gather_net_flux else None)
        irradiance = sum(w * gather(g, s, p[None], n[None], damping, exitance=exitance)[0]
                         for w, g, s in zip(weights, grids, specs) if w > 0)
        from_grid = albedo / math.pi * irradiance
    ref = None if reference is None else np.asarray(reference[y, x, :3], np.float64)
    return PickInfo(x, y, surface, position[:3], normal[:3], float(normal[3]), albedo,
                    np.asarray(result.direct[y, x], np.float64),
                    np.asarray(result.indirect[y, x], np.float64),
                    np.asarray(result.final_pixel(y, x), np.float64), ref, tuple(cells),
                    weights, from_grid)


@dataclass(frozen=True)
class CellAuditInfo:
    """The picked cell's audit records (explorer/lpv/audit.py CellAudit), read back from
    the GPU: summed over the propagation's steps and of its last step."""

    steps: int
    total: CellAudit
    last: CellAudit | None
    injected: np.ndarray
    """(3,) the cell's injected flux: flux of acc_N minus all it received (acc_N =
    grid_0 + Σ_t received_t holds per cell)."""


def cell_audit(result, cascade: int, index: CellIndex) -> CellAuditInfo | str:
    """The audit of cell ``index`` of ``cascade`` read from the GPU records of the frame
    (a small read, cached), or why there is none, in words."""
    level = result.cascades[cascade] if 0 <= cascade < len(result.cascades) else None
    records = None if level is None else level.cell_records
    if records is None:
        return ("this frame ran without the per-step energy audit, so its cells have no "
                "records (a frame measures it when a plot, a lesson, the Picked panel or a "
                "command asks: the window's next frame has them)")
    read = records.read(index)
    if read is None:
        return ("a newer propagation has overwritten this frame's records; they come "
                "back with its frame")
    total, last = read
    flux = C.SH_FLUX_FACTOR * np.asarray(level.accumulated[(slice(None),) + tuple(index)
                                                           + (0,)], np.float64)
    return CellAuditInfo(records.steps, total, last, flux - total.received)


def cell_at(result, cascade: int, world) -> CellIndex | None:
    """The cell of ``cascade`` holding the world point, None outside it."""
    _, specs = _cascades(result)
    if not 0 <= cascade < len(specs):
        return None
    index = specs[cascade].cell_index(np.asarray(world, np.float64))
    return tuple(int(v) for v in index) if specs[cascade].inside(index) else None


def pixel_of(result, world) -> tuple[int, int] | None:
    """The pixel of this frame that shows the surface point ``world``, or None when it
    lies outside the image or behind another surface (farther from the pixel's surface
    point than 3 pixel footprints)."""
    height, width = result.image_size
    world = np.asarray(world, np.float64)
    x, y = np.floor(project(result, world)).astype(np.int64)
    if not (0 <= x < width and 0 <= y < height):
        return None
    position = result.gbuffer_position[y, x]
    footprint = np.sqrt(max(float(result.gbuffer_normal[y, x, 3]), 0.0))
    if position[3] < 0.5 or np.linalg.norm(position[:3] - world) > 3.0 * footprint + 1e-6:
        return None
    return int(x), int(y)


def view_pixel(rect, mouse, image_size) -> tuple[int, int] | None:
    """The image pixel under ``mouse`` when the image of ``image_size`` (width, height) is
    drawn stretched over ``rect`` (x0, y0, x1, y1); both in the same units (the View panel
    uses framebuffer pixels: Runtime.view.view_rect), so the render scale drops out. None
    outside the image."""
    x0, y0, x1, y1 = rect
    width, height = image_size
    if x1 <= x0 or y1 <= y0:
        return None
    fx, fy = (mouse[0] - x0) / (x1 - x0), (mouse[1] - y0) / (y1 - y0)
    if not (0.0 <= fx < 1.0 and 0.0 <= fy < 1.0):
        return None
    return min(int(fx * width), width - 1), min(int(fy * height), height - 1)


# ------------------------------------------------------------------------- rays
def view_projection(result) -> np.ndarray:
    """(4, 4) projection·view of the frame's camera, as the G-buffer pass built it."""
    height, width = result.image_size
    lo, hi = result.scene_bounds
    projection = result.camera.projection_matrix(width / height, lo, hi)
    return projection @ result.camera.view_matrix()


def project(result, world) -> np.ndarray:
    """(..., 2) continuous pixel coordinates (x, y from the top) of world points."""
    height, width = result.image_size
    world = np.asarray(world, np.float64)
    clip = np.concatenate([world, np.ones(world.shape[:-1] + (1,))], -1) @ \
        view_projection(result).T
    ndc = clip[..., :2] / clip[..., 3:4]
    return np.stack([(ndc[..., 0] + 1.0) * 0.5 * width, (1.0 - ndc[..., 1]) * 0.5 * height],
                    -1)


def pixel_ray(result, x: float, y: float) -> tuple[np.ndarray, np.ndarray]:
    """(eye, unit direction) of the ray through the centre of pixel (x, y)."""
    height, width = result.image_size
    ndc = np.array([(x + 0.5) / width * 2.0 - 1.0, 1.0 - (y + 0.5) / height * 2.0, 1.0, 1.0])
    far = np.linalg.inv(view_projection(result)) @ ndc
    eye = np.asarray(result.camera.eye, np.float64)
    direction = far[:3] / far[3] - eye
    return eye, direction / np.linalg.norm(direction)


def slice_hit(result, spec, axis: str, layer: int, x: int, y: int, on_top: bool = False
              ) -> CellIndex | None:
    """The cell of the slice plane (through the centres of ``layer``'s cells) seen at
    pixel (x, y): where the pixel's ray crosses the plane inside the grid, if it does so
    in front of the surface the pixel shows (anywhere along the ray with ``on_top``)."""
    eye, direction = pixel_ray(result, x, y)
    a, _, _ = plane_axes(axis)
    if abs(direction[a]) < 1e-12:
        return None
    plane = spec.origin[a] + (layer + 0.5) * spec.cell_size
    t = (plane - eye[a]) / direction[a]
    if t <= 0:
        return None
    position = result.gbuffer_position[y, x]
    if not on_top and position[3] > 0.5:
        if t > float(np.linalg.norm(np.asarray(position[:3], np.float64) - eye)):
            return None
    index = spec.cell_index(eye + t * direction)
    index[a] = layer
    return tuple(int(v) for v in index) if spec.inside(index) else None

