"""Display images of a :class:`~explorer.lpv.pipeline.FrameResult` for every name in
``settings.VIEWS``: ``(H, W, 3)`` float32 in [0, 1].

Radiometric views are sRGB-encoded: final, direct and indirect as the display shows them
(the frame's display scale and tone curve, docs/MODEL.md "Display"), albedo (with the
geometry's edges darkened, explorer/lpv/surface_edges.py) and rsm-flux directly; data
views (positions, normals, grid slices) are mapped linearly to [0, 1] and not encoded,
so their values stay proportional to what they show.
"""

from __future__ import annotations

import numpy as np

from explorer.lpv.constants import SH_FLUX_FACTOR
from explorer.lpv.surface_edges import outlined_albedo
from explorer.lpv.twin.tonemap import display_encode, linear_to_srgb


def normalise(values: np.ndarray, percentile: float = 99.5) -> np.ndarray:
    """``values`` divided by their ``percentile``-th percentile of the nonzero entries
    (robust to a few very bright texels); all-zero input stays zero."""
    values = np.nan_to_num(np.asarray(values, np.float32))
    nonzero = np.abs(values[values != 0])
    if nonzero.size == 0:
        return np.zeros_like(values)
    scale = float(np.percentile(nonzero, percentile))
    return values / scale if scale > 0 else np.zeros_like(values)


def render_view(result, name: str, bounds=None, z: int | None = None,
                coefficient: int | None = None, exposure: float | None = None,
                cascade: int | None = None, positions: np.ndarray | None = None,
                display_scale: float | None = None) -> np.ndarray:
    """The image of ``result`` for view ``name``.

    Options: ``exposure`` (direct/indirect; default the frame's), ``z`` (slice index of
    the grid views; default the middle), ``coefficient`` (grid-slice: None shows the flux
    of each cell 2√π·c0 per colour; 0..3 (0..8 for L2) shows that SH coefficient signed
    around grey),
    ``cascade`` (grid views: which cascade, 0 = the finest, the default); ``positions``
    (cascade-weights: the G-buffer's world positions ``(H, W, 4)``, w = 1 where a surface
    is seen; :meth:`Pipeline.view` passes them); ``display_scale`` (final, direct,
    indirect: the scale before the tone curve; default the frame's ``display_scale``, e.g.
    another frame's to show two frames at one exposure).
    """
    settings = result.settings
    exposure = settings.exposure if exposure is None else float(exposure)
    scale = result.display_scale if display_scale is None else display_scale
    tone_map = getattr(settings, "tone_map", "linear-clip")
    if name == "final":
        return display_encode(result.final_image, scale, tone_map)
    if name in ("direct", "indirect"):
        return display_encode(exposure * getattr(result, name), scale, tone_map)
    if name == "albedo":
        return linear_to_srgb(outlined_albedo(result.albedo, result.gbuffer_position,
                                              result.gbuffer_normal))
    if name == "rsm-position":
        position, valid = result.rsm_position[..., :3], result.rsm_position[..., 3:] > 0.5
        lo = np.asarray(bounds[0] if bounds else position.min(axis=(0, 1)), np.float32)
        hi = np.asarray(bounds[1] if bounds else position.max(axis=(0, 1)), np.float32)
        image = (position - lo) / np.maximum(hi - lo, 1e-12)
        return np.clip(np.where(valid, image, 0.0), 0.0, 1.0).astype(np.float32)
    if name == "rsm-normal":
        valid = result.rsm_position[..., 3:] > 0.5
        image = np.where(valid, 0.5 * result.rsm_normal[..., :3] + 0.5, 0.0)
        return np.clip(image, 0.0, 1.0).astype(np.float32)
    if name == "rsm-flux":
        return linear_to_srgb(normalise(result.rsm_flux[..., :3]))
    if name == "grid-slice":
        return grid_slice(cascade_item(result, "accumulated", cascade), z, coefficient)
    if name == "geometry-volume":
        volume = cascade_item(result, "geometry", cascade)
        if volume is None:   # geometry volume off: nothing blocks
            nx, ny, _ = (n + 1 for n in result.grid_spec.cells)
            return np.zeros((ny, nx, 3), np.float32)
        index = volume.shape[2] // 2 if z is None else int(z)
        blocking = normalise(volume[:, :, index, 0]).T[::-1]
        return np.repeat(np.clip(blocking, 0.0, 1.0)[..., None], 3, axis=2).astype(np.float32)
    if name == "cascade-weights":
        if positions is None:
            raise ValueError("the cascade-weights view needs the G-buffer positions")
        return cascade_weight_image(result.cascade_specs or [result.grid_spec], positions)
    raise ValueError(f"unknown view {name!r}")


CASCADE_COLOURS = np.array([[0.95, 0.35, 0.15], [0.25, 0.8, 0.3], [0.25, 0.45, 0.95],
                            [0.9, 0.85, 0.2]], np.float32)
"""Display colour of cascades 0..3 in the cascade-weights view (finest: orange-red)."""


def cascade_weight_image(specs, positions: np.ndarray) -> np.ndarray:
    """Each visible pixel coloured by the final gather's blend weights (docs/MODEL.md
    "Cascades"): ``Σ_k W_k·colour_k``; pure colours where one cascade is used, mixtures in
    the blend bands, black background."""
    from explorer.lpv.cascades import blend_weights

    positions = np.asarray(positions, np.float32)
    weights = blend_weights(list(specs), positions[..., :3])
    image = weights @ CASCADE_COLOURS[: weights.shape[-1]]
    image *= (positions[..., 3:4] > 0.5)
    return np.clip(image, 0.0, 1.0).astype(np.float32)


def cascade_item(result, what: str, cascade: int | None):
    """Cascade ``cascade``'s accumulated grid or geometry volume (None/0: cascade 0, the
    FrameResult's own field)."""
    single = result.accumulated if what == "accumulated" else result.geometry_volume
    if not cascade:
        return single
    items = getattr(result, f"cascade_{what}", None) or [single]
    if not 0 <= int(cascade) < len(items):
        raise ValueError(f"cascade {cascade} does not exist: this frame has {len(items)} "
                         f"cascade(s), 0..{len(items) - 1}")
    return items[int(cascade)]


def grid_slice_values(grid: np.ndarray, z: int | None = None, coefficient: int | None = None
                      ) -> np.ndarray:
    """The numbers the grid-slice view shows, unscaled: one z slice of a
    ``(3, nx, ny, nz, C)`` grid as ``(ny, nx, 3)`` float32 (rows = y from the top, columns
    = x), each cell's flux 2√π·c0 [W] per colour, or SH coefficient ``coefficient`` [W/sr]
    when given."""
    n = grid.shape[3]
    index = n // 2 if z is None else int(z)
    if not 0 <= index < n:
        raise ValueError(f"slice z={index} is outside the grid (0..{n - 1})")
    cells = grid[:, :, :, index, :]                    # (3, x, y, C)
    if coefficient is None:
        values = SH_FLUX_FACTOR * cells[..., 0]
    else:
        last = grid.shape[-1] - 1   # 3 for L1, 8 for L2
        if coefficient not in range(last + 1):
            raise ValueError(f"coefficient must be 0..{last} for a grid of {last + 1} SH "
                             f"coefficients, got {coefficient}")
        values = cells[..., coefficient]
    # (3, x, y) -> rows = y from the top, columns = x
    return np.ascontiguousarray(np.transpose(values, (2, 1, 0))[::-1]).astype(np.float32)


def grid_slice_scale(values: np.ndarray, coefficient: int | None = None) -> float:
    """The value the grid-slice view shows at full brightness: the 99.5th percentile of
    the positive fluxes (:func:`normalise`), or for a coefficient the largest magnitude
    (shown as white; its negative as black, 0 as grey)."""
    if coefficient is None:
        positive = np.nan_to_num(np.maximum(values, 0.0))
        nonzero = positive[positive != 0]
        return float(np.percentile(nonzero, 99.5)) if nonzero.size else 0.0
    return float(np.max(np.abs(values))) if values.size else 0.0


def grid_slice(grid: np.ndarray, z: int | None = None, coefficient: int | None = None
               ) -> np.ndarray:
    """One z slice of a ``(3, N, N, N, 4)`` grid as an ``(N, N, 3)`` image (x to the right,
    y up): :func:`grid_slice_values` divided by :func:`grid_slice_scale`."""
    values = grid_slice_values(grid, z, coefficient)
    scale = grid_slice_scale(values, coefficient)
    if coefficient is None:
        image = linear_to_srgb(np.maximum(values, 0.0) / scale if scale > 0
                               else np.zeros_like(values))
    else:
        image = np.clip(0.5 + 0.5 * values / (scale or 1.0), 0.0, 1.0)
    return np.asarray(image, np.float32)
