"""Textures the UI layer owns: numpy images uploaded for imgui to draw.

The pipeline's own textures are only *shown* (by GL name); everything the inspect and
compare views derive from FrameResult arrays is uploaded here. Uploads happen only when
the image's ``version`` token changes, so a panel may ask every frame for free.
"""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from explorer.lpv.twin.tonemap import linear_to_srgb
from explorer.ui.texture_versions import versions_for


@dataclass
class _Entry:
    texture: moderngl.Texture
    version: object


class UiTextures:
    def __init__(self, ctx: moderngl.Context) -> None:
        self.ctx = ctx
        self._entries: dict[str, _Entry] = {}
        self._versions = versions_for(ctx)      # every write and release is told there

    def upload(self, key: str, image: np.ndarray, version: object = None,
               nearest: bool = True) -> int:
        """Upload ``image`` (H, W, 3|4) float in [0, 1] or uint8, top row first, under
        ``key``; returns the GL texture name for ``imgui.image``. With the same
        ``version`` as last time nothing is uploaded."""
        entry = self._entries.get(key)
        if entry is not None and version is not None and entry.version == version:
            return entry.texture.glo
        rgba = to_rgba8(image)
        height, width = rgba.shape[:2]
        if entry is None or entry.texture.size != (width, height):
            if entry is not None:
                self._release(entry)
            texture = self.ctx.texture((width, height), 4, dtype="f1")
            filt = moderngl.NEAREST if nearest else moderngl.LINEAR
            texture.filter = (filt, filt)
            entry = _Entry(texture, None)
            self._entries[key] = entry
        entry.texture.write(np.ascontiguousarray(rgba).tobytes(), alignment=1)
        self._versions.written(entry.texture.glo)
        entry.version = version
        return entry.texture.glo

    def get(self, key: str) -> int:
        entry = self._entries.get(key)
        return entry.texture.glo if entry else 0

    def discard(self, key: str) -> None:
        """Release the texture under ``key`` (nothing when there is none)."""
        entry = self._entries.pop(key, None)
        if entry is not None:
            self._release(entry)

    def release(self) -> None:
        for entry in self._entries.values():
            self._release(entry)
        self._entries.clear()

    def _release(self, entry: _Entry) -> None:
        self._versions.forget(entry.texture.glo)
        entry.texture.release()


def to_rgba8(image: np.ndarray) -> np.ndarray:
    """(H, W, 3|4) float [0, 1] or uint8 → (H, W, 4) uint8, top row first."""
    image = np.asarray(image)
    if image.ndim == 2:
        image = np.repeat(image[..., None], 3, axis=2)
    if image.ndim != 3 or image.shape[2] not in (3, 4):
        raise ValueError(f"expected an image shaped (H, W, 3|4), got {image.shape}")
    if image.dtype != np.uint8:
        image = np.clip(np.nan_to_num(image, nan=0.0), 0.0, 1.0)
        image = (image * 255.0 + 0.5).astype(np.uint8)
    if image.shape[2] == 3:
        alpha = np.full(image.shape[:2] + (1,), 255, dtype=np.uint8)
        image = np.concatenate([image, alpha], axis=2)
    return image


# A perceptually ordered dark-to-bright map (magma-like) given by a few control points;
# enough for a difference view and a scale bar without a plotting library.
_HEAT = np.array([
    [0.001, 0.000, 0.014],
    [0.232, 0.059, 0.437],
    [0.550, 0.161, 0.506],
    [0.868, 0.288, 0.409],
    [0.994, 0.624, 0.427],
    [0.987, 0.991, 0.750],
], dtype=np.float32)


def heat(values: np.ndarray) -> np.ndarray:
    """Map values in [0, 1] to RGB (..., 3) with the heat map."""
    t = np.clip(np.nan_to_num(np.asarray(values, dtype=np.float32)), 0.0, 1.0)
    pos = t * (len(_HEAT) - 1)
    low = np.minimum(pos.astype(np.int32), len(_HEAT) - 2)
    frac = (pos - low)[..., None]
    return _HEAT[low] * (1.0 - frac) + _HEAT[low + 1] * frac


def diverging(values: np.ndarray, scale: float) -> np.ndarray:
    """Signed values → blue (negative) / black / orange (positive), ±scale saturates."""
    v = np.nan_to_num(np.asarray(values, dtype=np.float32)) / max(scale, 1e-30)
    v = np.clip(v, -1.0, 1.0)[..., None]
    positive = np.array([1.0, 0.6, 0.15], dtype=np.float32)
    negative = np.array([0.2, 0.55, 1.0], dtype=np.float32)
    return np.where(v >= 0, v * positive, -v * negative)


def tonemap(image: np.ndarray, exposure: float = 1.0) -> np.ndarray:
    """Linear radiance → display sRGB in [0, 1] (clamp, then the sRGB curve)."""
    return linear_to_srgb(np.nan_to_num(np.asarray(image, dtype=np.float32)) * exposure)


def robust_max(values: np.ndarray, percentile: float = 99.5) -> float:
    """A high percentile of ``values`` (finite ones), at least a tiny positive number, so a
    few hot pixels do not wash out a scale."""
    finite = np.asarray(values, dtype=np.float64)
    finite = finite[np.isfinite(finite)]
    if finite.size == 0:
        return 1e-12
    return float(max(np.percentile(finite, percentile), 1e-12))
