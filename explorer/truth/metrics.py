"""Error metrics between an LPV image and the reference (pure numpy).

All functions take linear (H, W, 3) images and an optional region: a boolean (H, W) mask,
or rectangles ``(x0, y0, x1, y1)`` in pixels (half open, ``[x0, x1) × [y0, y1)``, rows
counted from the top of the array). Conventions for degenerate input, chosen so that
"the two agree" always reads the same:

* a region that selects no pixel raises :class:`EmptyRegionError` (a ValueError);
* when the reference is zero over the region, the relative L2 error is 0 if the test image
  is zero too and ``inf`` otherwise; the flux ratio is 1 if both are zero and ``inf``
  otherwise (a negative test sum over a zero reference gives ``-inf``).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from explorer.lpv.twin.tonemap import luminance

Rect = tuple[int, int, int, int]


class EmptyRegionError(ValueError):
    """The mask or rectangles select no pixel, so no statistic is defined."""


def _image(array: np.ndarray, name: str) -> np.ndarray:
    image = np.asarray(array, dtype=np.float64)
    if image.ndim != 3 or image.shape[2] != 3:
        raise ValueError(f"{name} must have shape (H, W, 3), got {image.shape}")
    if not np.all(np.isfinite(image)):
        raise ValueError(f"{name} contains NaN or infinite values")
    return image


def rect_mask(shape: tuple[int, int], rects: Iterable[Rect]) -> np.ndarray:
    """Boolean (H, W) mask of the union of half-open pixel rectangles (clipped to the
    image)."""
    height, width = shape
    mask = np.zeros((height, width), bool)
    for rect in rects:
        if len(rect) != 4:
            raise ValueError(f"a rectangle is (x0, y0, x1, y1), got {rect!r}")
        x0, y0, x1, y1 = (int(v) for v in rect)
        if x1 < x0 or y1 < y0:
            raise ValueError(f"rectangle {rect!r} has x1 < x0 or y1 < y0")
        mask[max(y0, 0):max(y1, 0), max(x0, 0):max(x1, 0)] = True
    return mask


def region_mask(shape: tuple[int, int], region=None) -> np.ndarray:
    """The (H, W) boolean mask for ``region`` (None = every pixel); raises
    :class:`EmptyRegionError` when it selects nothing."""
    if region is None:
        mask = np.ones(shape, bool)
    elif isinstance(region, np.ndarray) and region.dtype == bool:
        if region.shape != tuple(shape):
            raise ValueError(f"mask must have shape {tuple(shape)}, got {region.shape}")
        mask = region
    else:
        mask = rect_mask(shape, region)
    if not mask.any():
        raise EmptyRegionError("the region selects no pixels")
    return mask


def _images_and_mask(test: np.ndarray, reference: np.ndarray,
                     region) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Both images checked (same shape) and the mask of ``region`` over them."""
    test = _image(test, "test image")
    reference = _image(reference, "reference image")
    if test.shape != reference.shape:
        raise ValueError(f"images differ in shape: test {test.shape}, reference "
                         f"{reference.shape}")
    return test, reference, region_mask(test.shape[:2], region)


def _pair(test: np.ndarray, reference: np.ndarray, region) -> tuple[np.ndarray, np.ndarray]:
    test, reference, mask = _images_and_mask(test, reference, region)
    return test[mask], reference[mask]


def _ratio(numerator: float, denominator: float) -> float:
    """numerator/denominator with the module's zero conventions (0/0 = agreement)."""
    if denominator != 0.0:
        return numerator / denominator
    if numerator == 0.0:
        return 0.0
    return float(np.copysign(np.inf, numerator))


def relative_l2(test: np.ndarray, reference: np.ndarray, region=None) -> float:
    """``‖test − ref‖₂ / ‖ref‖₂`` over the region's pixels and all channels."""
    t, r = _pair(test, reference, region)
    return _ratio(float(np.linalg.norm(t - r)), float(np.linalg.norm(r)))


def rmse(test: np.ndarray, reference: np.ndarray, region=None) -> float:
    """Root mean square of ``test − ref`` over the region's pixels and all channels
    (in the images' unit, radiance)."""
    t, r = _pair(test, reference, region)
    return float(np.sqrt(np.mean((t - r) ** 2)))


def flux_ratio(test: np.ndarray, reference: np.ndarray, region=None,
               per_channel: bool = False) -> float | np.ndarray:
    """``Σ test / Σ ref`` over the region (all channels, or (3,) per channel): how much
    light the test image carries relative to the reference; 1 is exact."""
    t, r = _pair(test, reference, region)
    if per_channel:
        return np.array([_flux(float(t[:, c].sum()), float(r[:, c].sum())) for c in range(3)])
    return _flux(float(t.sum()), float(r.sum()))


def mean_radiance(image: np.ndarray, region=None) -> float:
    """Mean of ``image`` over the region's pixels and all channels (radiance): the two
    means of a region have the ratio :func:`flux_ratio` (same pixels, same count)."""
    image = _image(image, "image")
    return float(np.mean(image[region_mask(image.shape[:2], region)]))


def _flux(test_sum: float, reference_sum: float) -> float:
    if reference_sum == 0.0 and test_sum == 0.0:
        return 1.0
    return _ratio(test_sum, reference_sum)


@dataclass(frozen=True)
class ErrorStats:
    relative_l2: float
    rmse: float
    flux_ratio: float
    flux_ratio_rgb: tuple[float, float, float]
    pixels: int


def error_stats(test: np.ndarray, reference: np.ndarray, region=None) -> ErrorStats:
    """All metrics of the module for one region."""
    mask = region_mask(np.asarray(test).shape[:2], region)
    rgb = flux_ratio(test, reference, mask, per_channel=True)
    return ErrorStats(relative_l2(test, reference, mask), rmse(test, reference, mask),
                      flux_ratio(test, reference, mask), tuple(float(v) for v in rgb),
                      int(mask.sum()))


# --- false-colour error image ----------------------------------------------------------

# A blue–white–red diverging map (the end and middle colours of Moreland's "cool to warm"
# map, interpolated linearly in sRGB for simplicity): blue = test too dark, red = too
# bright, near white = agreement.
_DIVERGING = np.array([[0.230, 0.299, 0.754],
                       [0.865, 0.865, 0.865],
                       [0.706, 0.016, 0.150]])
ERROR_MODES = ("log2-ratio", "difference")
BACKGROUND = np.array([0.25, 0.25, 0.25])  # pixels outside the region


def diverging_colormap(values: np.ndarray, scale: float) -> np.ndarray:
    """RGB in [0, 1] for ``values`` in [−scale, scale] (clipped beyond)."""
    if not scale > 0:
        raise ValueError(f"scale must be positive, got {scale!r}")
    s = np.clip(np.asarray(values, np.float64) / scale, -1.0, 1.0)
    lower = _DIVERGING[0] + (s[..., None] + 1.0) * (_DIVERGING[1] - _DIVERGING[0])
    upper = _DIVERGING[1] + s[..., None] * (_DIVERGING[2] - _DIVERGING[1])
    return np.where(s[..., None] < 0, lower, upper)


@dataclass(frozen=True)
class ErrorImage:
    """``rgb`` (H, W, 3) in [0, 1]; ``values`` (H, W) the signed error that was coloured
    (NaN outside the region); colours saturate at ``±scale``."""

    rgb: np.ndarray
    values: np.ndarray
    scale: float
    mode: str


def error_image(test: np.ndarray, reference: np.ndarray, region=None, mode: str = "log2-ratio",
                scale: float | None = None, floor: float | None = None) -> ErrorImage:
    """False-colour error of the luminance.

    ``log2-ratio``: ``log2((test + floor)/(ref + floor))``, so ±1 means twice / half the
    reference; ``floor`` (default 1e-3 × the mean reference luminance of the region) keeps
    dark pixels from dominating. ``difference``: ``test − ref`` in radiance.
    ``scale`` None: the 99th percentile of |error| (at least a tiny positive value), so a
    few outliers do not wash the image out.
    """
    if mode not in ERROR_MODES:
        raise ValueError(f"mode must be one of {ERROR_MODES}, got {mode!r}")
    test_img, ref_img, mask = _images_and_mask(test, reference, region)
    t, r = luminance(test_img), luminance(ref_img)
    if mode == "difference":
        values = t - r
    else:
        if floor is None:
            floor = 1e-3 * float(np.abs(r[mask]).mean())
        floor = max(float(floor), 1e-30)
        values = np.log2(np.maximum(t, 0.0) + floor) - np.log2(np.maximum(r, 0.0) + floor)
    values = np.where(mask, values, np.nan)
    if scale is None:
        scale = float(np.percentile(np.abs(values[mask]), 99.0))
    scale = max(float(scale), 1e-12)
    rgb = np.where(mask[..., None], diverging_colormap(np.nan_to_num(values), scale),
                   BACKGROUND)
    return ErrorImage(rgb, values, scale, mode)
