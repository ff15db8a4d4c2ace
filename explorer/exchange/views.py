"""The float data behind each view (``render --out x.exr`` / ``x.npy``): the numbers the
PNG shows before any scaling, tone curve or encoding, in the PNG's orientation (row 0 at
the top)."""

from __future__ import annotations

import numpy as np

from explorer.lpv.views import grid_slice_values

FLOAT_VIEWS = {
    "final": "exposure·(direct + indirect) [W/(m² sr)], no display scale, no tone curve",
    "direct": "direct radiance [W/(m² sr)], no exposure",
    "indirect": "LPV radiance [W/(m² sr)], no exposure",
    "albedo": "linear diffuse reflectance",
    "rsm-position": "RSM world positions (xyz)",
    "rsm-normal": "RSM unit normals (xyz)",
    "rsm-flux": "RSM texel flux [W] per colour",
    "grid-slice": "flux per cell 2√π·c0 [W] per colour (or SH coefficient K [W/sr]); rows = "
                  "y from the top, columns = x",
    "geometry-volume": "blocking coefficient c0 of the geometry cells of one z slice "
                       "(unitless); rows = y from the top",
    "cascade-weights": "each pixel's cascade colours weighted by the gather's blend weights",
}


def float_view(result, view: str, z: int | None = None, coefficient: int | None = None,
               cascade: int | None = None, positions=None) -> np.ndarray:
    """The float image of ``view`` for ``result`` (:data:`FLOAT_VIEWS` says what it holds)."""
    from explorer.lpv.views import cascade_item, cascade_weight_image

    if view == "final":
        return np.asarray(result.final_image, np.float32)
    if view in ("direct", "indirect", "albedo"):
        return np.asarray(getattr(result, view), np.float32)
    if view.startswith("rsm-"):
        return np.asarray(getattr(result, view.replace("-", "_"))[..., :3], np.float32)
    if view == "grid-slice":
        return grid_slice_values(cascade_item(result, "accumulated", cascade), z, coefficient)
    if view == "geometry-volume":
        volume = cascade_item(result, "geometry", cascade)
        if volume is None:
            nx, ny, _ = (n + 1 for n in result.grid_spec.cells)
            return np.zeros((ny, nx), np.float32)
        index = volume.shape[2] // 2 if z is None else int(z)
        return np.ascontiguousarray(volume[:, :, index, 0].T[::-1], np.float32)
    if view == "cascade-weights":
        return cascade_weight_image(result.cascade_specs or [result.grid_spec], positions)
    raise ValueError(f"unknown view {view!r}")
