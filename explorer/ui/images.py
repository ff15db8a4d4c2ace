"""Display images the UI derives from FrameResult arrays (pure numpy, no GL, testable).

Every function returns (H, W, 3) float32 in [0, 1], top row first, ready for
:meth:`explorer.ui.textures.UiTextures.upload`.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from explorer.lpv import constants as C
from explorer.lpv.twin.tonemap import luminance
from explorer.ui.textures import diverging, heat, robust_max, tonemap


def auto_exposure(final_image: np.ndarray, exposure_used: float, key: float = 0.85) -> float:
    """The exposure that puts the 99th percentile of luminance at ``key``: lets the two
    sides of a comparison whose fluxes differ by π or 4π be seen side by side."""
    unexposed = luminance(final_image) / max(exposure_used, 1e-30)
    level = robust_max(unexposed, 99.0)
    return float(key / level) if level > 1e-12 else 1.0


def difference(a: np.ndarray, b: np.ndarray, scale: float = 0.0) -> tuple[np.ndarray, float]:
    """False-colour |a − b| (luminance) and the value at the top of the colour scale
    (``scale``, or the 99.5th percentile when 0)."""
    a = np.asarray(a, dtype=np.float32)
    b = np.asarray(b, dtype=np.float32)
    if a.shape != b.shape:
        raise ValueError(f"the two images differ in shape: {a.shape} vs {b.shape}")
    delta = np.abs(luminance(a) - luminance(b))
    top = scale if scale > 0 else robust_max(delta)
    return heat(delta / top), float(top)


def rsm_image(buffer: np.ndarray, kind: str) -> np.ndarray:
    """An RSM buffer (Hr, Wr, 4) as a picture: positions normalised to their bounds,
    normals mapped from [−1, 1], flux tonemapped at its robust maximum."""
    data = np.asarray(buffer, dtype=np.float32)[..., :3]
    if kind == "rsm-normal":
        return np.clip(data * 0.5 + 0.5, 0.0, 1.0)
    if kind == "rsm-position":
        finite = data[np.isfinite(data).all(axis=-1)]
        if finite.size == 0:
            return np.zeros_like(data)
        lo, hi = finite.min(axis=0), finite.max(axis=0)
        return np.clip((data - lo) / np.maximum(hi - lo, 1e-12), 0.0, 1.0)
    return tonemap(data, 1.0 / robust_max(data))


def sh_basis(direction: np.ndarray, sh_order: int = 1) -> np.ndarray:
    """SH basis in docs/MODEL.md's order and signs at a unit direction: L1 (c0, −c1·y,
    c1·z, −c1·x), with ``sh_order`` 2 followed by band 2 (c2·xy, −c2·yz, c3·(3z²−1),
    −c2·xz, c4·(x²−y²)), from the generated constants the shaders use."""
    x, y, z = (float(v) for v in direction)
    basis = [C.SH_C0, -C.SH_C1 * y, C.SH_C1 * z, -C.SH_C1 * x]
    if sh_order == 2:
        basis += [C.SH_L2_C2 * x * y, -C.SH_L2_C2 * y * z, C.SH_L2_C3 * (3.0 * z * z - 1.0),
                  -C.SH_L2_C2 * x * z, C.SH_L2_C4 * (x * x - y * y)]
    return np.array(basis, dtype=np.float32)


def direction_from_angles(azimuth_deg: float, elevation_deg: float) -> np.ndarray:
    az, el = math.radians(azimuth_deg), math.radians(elevation_deg)
    return np.array([math.cos(el) * math.sin(az), math.sin(el), math.cos(el) * math.cos(az)])


def grid_slice(grid: np.ndarray, z: int, component: str, direction=None,
               scale: float = 0.0) -> tuple[np.ndarray, float]:
    """One z slice of a (3, N, N, N, 4) SH grid as an image (rows = y, top = high y).

    ``component`` "intensity": the radiant intensity toward ``direction``, clamped at 0,
    on a heat scale per channel; "sh0".."sh3": that coefficient, signed (blue negative).
    Returns the image and the value that saturates the colours."""
    grid = np.asarray(grid, dtype=np.float32)
    if grid.ndim != 5 or grid.shape[0] != 3 or grid.shape[4] not in (4, 9):
        raise ValueError(f"expected a grid shaped (3, N, N, N, 4) or (3, N, N, N, 9), got "
                         f"{grid.shape}")
    z = int(np.clip(z, 0, grid.shape[3] - 1))
    cells = grid[:, :, :, z, :]                     # (3, x, y, 4)
    if component == "intensity":
        towards = direction if direction is not None else (0.0, 1.0, 0.0)
        unit = np.asarray(towards, np.float64) / np.linalg.norm(towards)
        basis = sh_basis(unit, 2 if grid.shape[4] == 9 else 1)   # L2: Settings.sh_order 2
        values = np.maximum(np.einsum("cxyk,k->xyc", cells, basis), 0.0)
        top = scale if scale > 0 else robust_max(values)
        image = tonemap(values, 1.0 / top)
    else:
        k = int(component[-1])
        values = np.transpose(cells[..., k], (1, 2, 0))   # (x, y, 3)
        top = scale if scale > 0 else robust_max(np.abs(values))
        image = diverging(values.sum(axis=-1) / 3.0, top)
    # (x, y, ·) → rows y from the top (high y first), columns x
    return np.ascontiguousarray(np.transpose(image, (1, 0, 2))[::-1]), float(top)


def volume_slice(volume: np.ndarray, z: int, scale: float = 0.0) -> tuple[np.ndarray, float]:
    """One z slice of the geometry volume (M, M, M, 4): the blocking of the band-0
    coefficient, signed band 1 ignored, on the heat scale."""
    volume = np.asarray(volume, dtype=np.float32)
    if volume.ndim != 4 or volume.shape[3] != 4:
        raise ValueError(f"expected a volume shaped (M, M, M, 4), got {volume.shape}")
    z = int(np.clip(z, 0, volume.shape[2] - 1))
    values = volume[:, :, z, 0] * C.SH_C0             # blocking seen from every direction
    top = scale if scale > 0 else robust_max(np.abs(values))
    image = heat(np.abs(values) / top)
    return np.ascontiguousarray(np.transpose(image, (1, 0, 2))[::-1]), float(top)


def flux_of_grid(grid: np.ndarray) -> float:
    """Total flux (all channels) held by an SH grid: 2√π·Σ coefficient 0 (MODEL.md)."""
    return float(C.SH_FLUX_FACTOR * np.asarray(grid, dtype=np.float64)[..., 0].sum())


def vpl_groups(positions: np.ndarray, flux: np.ndarray, max_points: int = 4096,
               levels: int = 3) -> list[tuple[tuple[float, float, float], np.ndarray]]:
    """VPLs grouped by colour for a scatter plot: each VPL's flux colour (normalised by the
    brightest channel of the brightest VPL, then brightened with a square root) quantised
    to ``levels`` steps per channel. Dark VPLs are dropped and at most ``max_points`` are
    kept (a fixed pseudo-random subset, so the picture does not flicker).
    Returns [(rgb, positions (k, 3) float64), ...]."""
    positions = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
    flux = np.asarray(flux, dtype=np.float64).reshape(-1, 3)
    if positions.shape != flux.shape:
        raise ValueError(f"positions {positions.shape} and flux {flux.shape} differ")
    strength = flux.max(axis=1)
    lit = np.isfinite(strength) & (strength > 1e-6 * max(float(np.nanmax(strength, initial=0)),
                                                          1e-30))
    positions, flux = positions[lit], flux[lit]
    if len(positions) > max_points:
        keep = np.sort(np.random.default_rng(0).choice(len(positions), max_points,
                                                       replace=False))
        positions, flux = positions[keep], flux[keep]
    if len(positions) == 0:
        return []
    colour = np.sqrt(np.clip(flux / max(float(flux.max()), 1e-30), 0.0, 1.0))
    codes = np.rint(colour * (levels - 1)).astype(np.int64)
    key = (codes[:, 0] * levels + codes[:, 1]) * levels + codes[:, 2]
    groups = []
    for value in np.unique(key):
        members = key == value
        rgb = tuple(float(c) / (levels - 1) for c in codes[members][0])
        groups.append((tuple(max(c, 0.15) for c in rgb), positions[members]))
    return groups


def write_png(pixels: np.ndarray, path: str | Path) -> None:
    from PIL import Image

    from explorer.safe_files import write_atomically

    path = Path(path)
    if path.parent and not path.parent.exists():
        path.parent.mkdir(parents=True, exist_ok=True)
    image = Image.fromarray(np.asarray(pixels, dtype=np.uint8), "RGB")
    # whole or not at all: a full disk or an interrupt leaves no half-written PNG
    write_atomically(path, lambda partial: image.save(partial, format="PNG"))
