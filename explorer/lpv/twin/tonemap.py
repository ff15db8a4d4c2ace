"""Display encoding: exposure scale, tone curve and sRGB, and the auto exposure
(docs/MODEL.md "Display"). The numpy twin of ``shaders/tonemap.glsl``.

* ``"linear-clip"``: the exposed radiance clipped to [0, 1] (every value above 1 shows as
  white);
* ``"filmic"``: Narkowicz's fit of the ACES filmic curve
  ``x(2.51x + 0.03)/(x(2.43x + 0.59) + 0.14)``, which rolls highlights off towards 1
  instead of clipping them, so the scene can be exposed brighter and the dim indirect
  light (colour bleeding) shows.

Auto exposure: the log-average luminance ``L̄ = exp(mean(log(δ + L)))`` (Reinhard et al.
2002, "Photographic tone reproduction") and the scale ``key/L̄`` that exposes it at
``key``. The average runs over the pixels that show a surface *and* lie between the 70th
and 98th percentile of their luminance (the bright part of the image, as histogram
metering in game engines does): spot-lit rooms and sunlit courtyards are mostly shadow,
and a mean over every pixel would expose for the shadows and burn out the lit surfaces;
the top 2 % (highlights) are left out too. ``δ`` is a tiny fraction of the brightest
luminance, so an unlit pixel in the window keeps ``L̄`` finite and the scale stays exactly
inversely proportional to the light's flux (auto exposure undoes any change of flux).
"""

from __future__ import annotations

import math

import numpy as np

from explorer.lpv.settings import TONE_MAPS

ACES_FIT = (2.51, 0.03, 2.43, 0.59, 0.14)
"""Coefficients a, b, c, d, e of ``x(ax + b)/(x(cx + d) + e)`` (shaders/tonemap.glsl)."""
AUTO_EXPOSURE_KEY = 0.45
"""The exposed log-average luminance of the metered window under auto exposure: the lit
surfaces land on the filmic curve's upper mid tones (0.45 → 0.58, sRGB 0.79)."""
METERED_PERCENTILES = (70.0, 98.0)
"""The luminance window (percentiles of the surface pixels) the auto exposure averages."""
LOG_AVERAGE_FLOOR = 1e-4
"""``δ`` of the log average, relative to the brightest luminance."""
REC709_LUMA = np.array([0.2126, 0.7152, 0.0722])
"""Luminance weights of linear Rec. 709 / sRGB primaries."""


def tone_map_index(name: str) -> int:
    """The GLSL constant of a tone map name; ValueError naming the choices otherwise."""
    if name not in TONE_MAPS:
        raise ValueError(f"tone_map must be one of {TONE_MAPS}, got {name!r}")
    return TONE_MAPS.index(name)


def filmic(x: np.ndarray) -> np.ndarray:
    """The ACES fit of ``tone_map_filmic`` (shaders/tonemap.glsl), clamped to [0, 1]."""
    a, b, c, d, e = ACES_FIT
    x = np.asarray(x, np.float64)
    return np.clip(x * (a * x + b) / (x * (c * x + d) + e), 0.0, 1.0)


def linear_to_srgb(linear: np.ndarray) -> np.ndarray:
    """The sRGB encoding (IEC 61966-2-1) of linear values clipped to [0, 1], float32."""
    c = np.clip(np.nan_to_num(np.asarray(linear, np.float32)), 0.0, 1.0)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1.0 / 2.4) - 0.055
                    ).astype(np.float32)


def display_encode(linear: np.ndarray, scale: float = 1.0, tone_map: str = "filmic"
                   ) -> np.ndarray:
    """A linear image as shown: ``srgb(curve(max(scale·linear, 0)))``, float32 in [0, 1]
    (``display_encode`` of shaders/tonemap.glsl)."""
    x = np.maximum(np.nan_to_num(np.asarray(linear, np.float64)) * float(scale), 0.0)
    if tone_map_index(tone_map) == TONE_MAPS.index("filmic"):
        x = filmic(x)
    return linear_to_srgb(x)


def luminance(image: np.ndarray) -> np.ndarray:
    """Rec. 709 luminance of a linear ``(..., 3)`` image."""
    return np.asarray(image, np.float64)[..., :3] @ REC709_LUMA


def log_average_luminance(image: np.ndarray, mask: np.ndarray | None = None,
                          percentiles: tuple[float, float] = METERED_PERCENTILES) -> float:
    """``exp(mean(log(δ + L)))`` over the pixels of ``mask`` (all when None) whose
    luminance ranks between the two ``percentiles`` of theirs (``(0, 100)``: all of them;
    at least one pixel), ``δ`` = :data:`LOG_AVERAGE_FLOOR` × the brightest; 0 when none
    is lit."""
    return log_average_of(metered_luminance(image, mask), percentiles)


def metered_luminance(image: np.ndarray, mask: np.ndarray | None = None) -> np.ndarray:
    """The luminances :func:`log_average_luminance` averages: of the pixels of ``mask``
    (all when None), non-finite ones as 0, negative ones as 0, flat (the first half of it;
    the window's display stage takes the halves in units of their own)."""
    lum = luminance(image)
    if not np.isfinite(lum).all():      # nan_to_num copies even when nothing is to change
        lum = np.nan_to_num(lum)
    if mask is not None:
        lum = lum[np.asarray(mask, bool)]
    return np.maximum(lum.ravel(), 0.0)


def log_average_of(lum: np.ndarray,
                   percentiles: tuple[float, float] = METERED_PERCENTILES) -> float:
    """:func:`log_average_luminance` of the luminances :func:`metered_luminance` gives."""
    peak = float(lum.max()) if lum.size else 0.0
    if not peak > 0.0:
        return 0.0
    # the window by rank, so it is never empty: the sorted values from ⌊n·p_low/100⌋ up to
    # ⌈n·p_high/100⌉ (exclusive), at least one. A partition at the two ranks puts the
    # window's values between them (in some order: the mean does not need one) in linear
    # time; a sort of a 960×540 frame took as long as a band of the gather.
    count = len(lum)
    first = min(math.floor(count * percentiles[0] / 100.0), count - 1)
    stop = max(math.ceil(count * percentiles[1] / 100.0), first + 1)
    ranked = np.partition(lum, sorted({first, stop - 1}))
    window = ranked[first:stop]
    delta = LOG_AVERAGE_FLOOR * peak
    logs = np.log(delta + window)
    # np.mean's own sum and division, without its Python wrapper (the same bits)
    return float(np.exp(np.add.reduce(logs) / logs.size))


def auto_exposure_scale(image: np.ndarray, mask: np.ndarray | None = None,
                        key: float = AUTO_EXPOSURE_KEY) -> float:
    """``key / L̄`` of ``image`` (1 when nothing is lit): the scale that exposes the image's
    log-average luminance at ``key``."""
    return exposure_for(log_average_luminance(image, mask), key)


def exposure_for(average: float, key: float = AUTO_EXPOSURE_KEY) -> float:
    """``key / average``, 1 when nothing is lit (``average`` 0)."""
    return float(key / average) if average > 0.0 else 1.0


def clipped_fraction(linear: np.ndarray, scale: float = 1.0, tone_map: str = "linear-clip"
                     ) -> float:
    """Fraction of the pixels whose displayed colour saturates a channel (reaches 1
    before encoding): a measure of lost highlights."""
    x = np.maximum(np.nan_to_num(np.asarray(linear, np.float64)) * float(scale), 0.0)
    if tone_map_index(tone_map) == TONE_MAPS.index("filmic"):
        x = filmic(x)
    return float(np.mean(np.any(x >= 1.0, axis=-1)))
