"""The error of an LPV frame against the one-bounce reference, computed a few tiles at a
time so that a window can keep drawing (and cancel) while it runs.

:class:`ProgressiveReference` splits the frame's G-buffer into square tiles and runs the
reference pass (:class:`~explorer.truth.reference.ReferencePass`) on one tile per
:meth:`~ProgressiveReference.step`, or on a few of its dispatches (a tile × a chunk of
VPLs) per :meth:`~ProgressiveReference.advance`, with the VPL textures and the BVH built
once. Each pixel sums the same VPLs in the same order as a one-shot
:func:`~explorer.truth.render.reference_for_frame`, so the finished image is that image.

:class:`ErrorJob` measures one configuration: it renders the LPV frame at the
measurement's size (:func:`measured_settings`: a smaller image and RSM than the window's,
because the reference costs pixels × VPLs), builds the scene's BVH for the shadow rays,
then the reference, then the metrics of ``explorer/truth/metrics.py`` over the pixels
that see a surface; every step in units small enough for a window's frame.

:func:`pixel_reference` is the same reference at one pixel of a frame (a 1×1 tile at the
frame's resolution, the frame's own VPLs): the window's picked pixel
(:func:`pixel_job` makes it steppable).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from explorer.truth.metrics import ErrorImage, ErrorStats, error_image, error_stats
from explorer.truth.reference import (
    GBuffer,
    ReferenceGather,
    ReferencePass,
    default_ray_offset,
    outgoing_radiance,
)

REFERENCE_MODES = ("visible", "unoccluded")
"""visible: a shadow ray per VPL and pixel; unoccluded: no visibility (what an LPV without
a geometry volume approximates)."""
FRAME_SHARE, BVH_SHARE = 0.05, 0.2
"""ErrorJob.fraction: the share of the LPV frame and of the BVH (visible reference)."""
LOG2_SCALE = 3.0
"""The error image saturates at 8× too bright or too dark (as ``lpv-explorer compare``)."""


@dataclass(frozen=True)
class Measurement:
    """How a configuration is measured: the image's longer side in pixels, the RSM size
    (VPLs = rsm_size², before the lit ones are picked) and the reference's visibility."""

    size: int = 128
    rsm_size: int = 64
    reference: str = "visible"

    def __post_init__(self) -> None:
        if self.reference not in REFERENCE_MODES:
            raise ValueError(f"reference must be one of {REFERENCE_MODES}, got "
                             f"{self.reference!r}")
        if not 8 <= self.size <= 2048 or not 1 <= self.rsm_size <= 1024:
            raise ValueError(f"size must be in [8, 2048] and rsm_size in [1, 1024], got "
                             f"{self.size}, {self.rsm_size}")


def measured_settings(settings, measurement: Measurement, aspect: float = 1.0):
    """``settings`` as measured: the image ``measurement.size`` pixels on its longer side
    with the given width/height ``aspect``, the RSM ``measurement.rsm_size``², everything
    else (scene, camera, light, grid, corrections, ...) unchanged."""
    aspect = float(aspect) if aspect > 0 else 1.0
    if aspect >= 1.0:
        width, height = measurement.size, max(8, round(measurement.size / aspect))
    else:
        width, height = max(8, round(measurement.size * aspect)), measurement.size
    return settings.with_changes(width=width, height=height, rsm_size=measurement.rsm_size)


def tiles(width: int, height: int, tile: int) -> list[tuple[int, int, int, int]]:
    """Half-open pixel rectangles (x0, y0, x1, y1) covering the image, row by row."""
    return [(x, y, min(x + tile, width), min(y + tile, height))
            for y in range(0, height, tile) for x in range(0, width, tile)]


def crop(gbuffer: GBuffer, rect: tuple[int, int, int, int]) -> GBuffer:
    x0, y0, x1, y1 = rect
    return GBuffer(np.asarray(gbuffer.position)[y0:y1, x0:x1],
                   np.asarray(gbuffer.normal)[y0:y1, x0:x1],
                   np.asarray(gbuffer.albedo)[y0:y1, x0:x1],
                   np.asarray(gbuffer.valid)[y0:y1, x0:x1])


class ProgressiveReference:
    """The reference radiance of ``frame`` (a FrameResult), one tile per :meth:`step`, or
    a few dispatches (a tile × a chunk of VPLs each) per :meth:`advance`."""

    def __init__(self, ctx, frame, visibility: bool, tile: int = 32,
                 min_distance: float | None = None, scene=None,
                 region: tuple[int, int, int, int] | None = None, bvh=None,
                 reference_pass: ReferencePass | None = None, vpl_chunk: int = 4096) -> None:
        """``region`` (x0, y0, x1, y1): only these pixels (the others stay zero); ``bvh``:
        the scene's prebuilt :class:`~explorer.truth.bvh.Bvh` for the shadow rays (built
        here from ``scene`` otherwise); ``reference_pass``: a pass to use (and not
        release), so that its program is compiled once for many references;
        ``vpl_chunk``: VPLs per dispatch (:meth:`ReferencePass.run`)."""
        from explorer.lpv.vpl import VplTextures
        from explorer.truth.bvh import build_bvh
        from explorer.truth.gbuffer import gbuffer_from_frame, scene_for, scene_triangles
        from explorer.truth.render import lit_vpls

        if tile < 1:
            raise ValueError(f"tile must be >= 1, got {tile}")
        self.ctx = ctx
        self.visibility = bool(visibility)
        self.min_distance = (0.5 * frame.grid_spec.cell_size if min_distance is None
                             else float(min_distance))
        needs_scene = (visibility and bvh is None) or frame.gbuffer_position is None
        if scene is None and needs_scene:
            scene = scene_for(frame.settings)
        self.gbuffer = gbuffer_from_frame(frame, scene, ctx)
        if visibility and bvh is None:
            bvh = build_bvh(scene_triangles(scene))
        self.bvh = bvh if visibility else None
        self.ray_offset = default_ray_offset(
            self.bvh.triangles if self.bvh is not None else None, self.gbuffer)
        width, height = self.gbuffer.size
        x0, y0, x1, y1 = (0, 0, width, height) if region is None else region
        if not (0 <= x0 < x1 <= width and 0 <= y0 < y1 <= height):
            raise ValueError(f"region {region} is not a rectangle of the {width}x{height} "
                             "image")
        vpls = lit_vpls(frame.vpls)
        self.vpls = VplTextures.from_arrays(ctx, vpls) if vpls.count else None
        self.irradiance = np.zeros((height, width, 3), np.float32)
        self.tiles = [(x0 + a, y0 + b, x0 + c, y0 + d)
                      for a, b, c, d in tiles(x1 - x0, y1 - y0, tile)]
        self.tile_size = tile
        self.vpl_chunk = int(vpl_chunk)
        self.done_tiles = 0
        self._owns_pass = reference_pass is None
        self._pass = ReferencePass(ctx) if reference_pass is None else reference_pass
        self._gather: ReferenceGather | None = None
        """The dispatches of the tile in progress."""

    @property
    def fraction(self) -> float:
        if not self.tiles:
            return 1.0
        partial = self._gather.done / self._gather.total if self._gather is not None and \
            self._gather.total else 0.0
        return (self.done_tiles + partial) / len(self.tiles)

    @property
    def done(self) -> bool:
        return self.done_tiles >= len(self.tiles)

    def step(self) -> bool:
        """Gather the next tile (all its dispatches); True once every tile is done."""
        if self.done:
            return True
        gather = self._tile_gather()
        if gather is None:
            self.done_tiles += 1                # no surface or no VPL: zero
        else:
            gather.step(gather.total - gather.done)
            self._finish_tile()
        return self.done

    def advance(self, budget_s: float) -> int:
        """Dispatches for about ``budget_s`` seconds, at least one while any is left
        (tiles without a surface cost none); returns how many ran."""
        start = time.perf_counter()
        ran = 0
        while not self.done:
            left = budget_s - (time.perf_counter() - start)
            if ran and left <= 0.0:
                break
            gather = self._tile_gather()
            if gather is None:
                self.done_tiles += 1
                continue
            ran += gather.advance(max(left, 0.0))
            if gather.finished:
                self._finish_tile()
        return ran

    def _tile_gather(self) -> ReferenceGather | None:
        """The current tile's gather (started on first use); None for a tile with nothing
        to gather."""
        if self._gather is None:
            part = crop(self.gbuffer, self.tiles[self.done_tiles])
            if self.vpls is None or not np.asarray(part.valid).any():
                return None
            self._gather = self._pass.start(part, self.vpls, self.min_distance, self.bvh,
                                            self.visibility, self.ray_offset,
                                            tile_size=self.tile_size,
                                            vpl_chunk=self.vpl_chunk)
        return self._gather

    def _finish_tile(self) -> None:
        x0, y0, x1, y1 = self.tiles[self.done_tiles]
        try:
            self.irradiance[y0:y1, x0:x1] = self._gather.irradiance()
        finally:
            self._gather.release()
            self._gather = None
        self.done_tiles += 1

    def radiance(self) -> np.ndarray:
        """Outgoing radiance a/π·E (H, W, 3) of the tiles done so far (zero elsewhere)."""
        return outgoing_radiance(self.gbuffer, self.irradiance)

    def radiance_at(self, x: int, y: int) -> np.ndarray:
        """(3,) float64 outgoing radiance a/π·E of pixel (x, y) (zero without a surface)."""
        if not bool(np.asarray(self.gbuffer.valid)[y, x]):
            return np.zeros(3)
        albedo = np.asarray(self.gbuffer.albedo, np.float64)[y, x]
        return albedo / np.pi * self.irradiance[y, x].astype(np.float64)

    def release(self) -> None:
        if self._gather is not None:
            self._gather.release()
            self._gather = None
        if self._owns_pass:
            self._pass.release()
        if self.vpls is not None:
            for texture in (self.vpls.position, self.vpls.normal, self.vpls.flux):
                texture.release()
            self.vpls = None


def pixel_job(ctx, frame, x: int, y: int, visibility: bool, scene=None, bvh=None,
              reference_pass: ReferencePass | None = None,
              vpl_chunk: int = 4096) -> ProgressiveReference:
    """The reference of the one pixel (x, y) of ``frame`` (row 0 at the top) as a
    :class:`ProgressiveReference` of a 1×1 tile: :func:`pixel_reference` runs it at once,
    a window a few VPL chunks per frame (its value: ``radiance_at(x, y)`` once done)."""
    height, width = frame.image_size
    if not (0 <= x < width and 0 <= y < height):
        raise ValueError(f"pixel ({x}, {y}) is outside the {width}x{height} frame")
    return ProgressiveReference(ctx, frame, visibility, tile=1, scene=scene,
                                region=(int(x), int(y), int(x) + 1, int(y) + 1), bvh=bvh,
                                reference_pass=reference_pass, vpl_chunk=vpl_chunk)


def pixel_reference(ctx, frame, x: int, y: int, visibility: bool, scene=None,
                    bvh=None) -> np.ndarray:
    """(3,) one-bounce reference radiance of pixel (x, y) (row 0 at the top) of ``frame``
    (a FrameResult), in the units of ``frame.indirect``: every lit VPL of the frame
    gathered at that pixel's surface point, with shadow rays when ``visibility``. The
    pixel is a 1×1 tile of the frame's own image, so it sums the same VPLs in the same
    order as the full reference image (:func:`~explorer.truth.render.reference_for_frame`)
    and equals its pixel."""
    reference = pixel_job(ctx, frame, x, y, visibility, scene, bvh)
    try:
        reference.step()
        return reference.radiance_at(int(x), int(y))
    finally:
        reference.release()


@dataclass(frozen=True)
class ErrorResult:
    """A finished measurement: the LPV's and the reference's indirect radiance, the
    pixels that count, the metrics and the false-colour error."""

    settings: object
    """The Settings measured (``measured_settings`` of the configuration)."""
    measurement: Measurement
    lpv: np.ndarray
    reference: np.ndarray
    valid: np.ndarray
    stats: ErrorStats
    error: ErrorImage


class ErrorJob:
    """Measures ``settings`` with ``measurement`` (LPV frame, the scene's BVH for the
    visible reference, the reference, the metrics) in small units, so that the window stays
    responsive: call :meth:`advance` until :attr:`result` is set (each call does at least
    one unit: a pipeline job's unit, a BVH node, a tile × a chunk of VPLs of the reference;
    :attr:`units` says how many); :meth:`release` frees the GL objects at any time."""

    def __init__(self, settings, measurement: Measurement, aspect: float = 1.0) -> None:
        self.measurement = measurement
        self.settings = measured_settings(settings, measurement, aspect)
        self.visibility = measurement.reference == "visible"
        self.frame = None
        self.bvh = None
        self.reference: ProgressiveReference | None = None
        self.result: ErrorResult | None = None
        self.units = 0
        """Units of work the last :meth:`advance` did."""
        self._job = None
        self._scene = None
        self._builder = None

    @property
    def fraction(self) -> float:
        if self.result is not None:
            return 1.0
        if self.frame is None:
            return 0.0
        bvh_share = BVH_SHARE if self.visibility else 0.0
        if self.reference is None:
            built = self._builder.fraction if self._builder is not None else 0.0
            return FRAME_SHARE + bvh_share * (1.0 if self.bvh is not None else built)
        return FRAME_SHARE + bvh_share + (1.0 - FRAME_SHARE - bvh_share) * \
            self.reference.fraction

    @property
    def stage(self) -> str:
        if self.result is not None:
            return "done"
        if self.frame is None:
            return "LPV frame"
        if self.visibility and self.bvh is None:
            return "building BVH"
        return "reference"

    def advance(self, ctx, pipeline, budget_s: float) -> bool:
        """Work for about ``budget_s`` seconds (at least one unit); True when done.
        ``pipeline`` renders the LPV frame on ``ctx`` (the caller keeps it between jobs, so
        its programs are compiled once)."""
        from explorer.truth.bvh import BvhBuilder
        from explorer.truth.gbuffer import scene_for, scene_triangles

        start = time.perf_counter()
        self.units = 0
        if self.result is not None:
            return True
        if self.frame is None:
            if self._job is None:
                self._job = pipeline.start(self.settings)
            self._job.advance(budget_s * 1e3)
            self.units = 1
            if self._job.done:
                self.frame, self._job = self._job.result, None
                # the pipeline has the scene loaded: pose it, do not load it again
                self._scene = scene_for(self.frame.settings,
                                        getattr(pipeline, "base_scene", None))
            return False
        left = budget_s - (time.perf_counter() - start)
        if self.visibility and self.bvh is None:
            if self._builder is None:
                self._builder = BvhBuilder(scene_triangles(self._scene))
                return False
            self.units = self._builder.advance(left)
            if self._builder.done:
                self.bvh, self._builder = self._builder.result(), None
            return False
        if self.reference is None:
            self.reference = ProgressiveReference(ctx, self.frame, self.visibility,
                                                  scene=self._scene, bvh=self.bvh)
            return False
        self.units = self.reference.advance(left)
        if not self.reference.done:
            return False
        self.result = self._finish()
        self.reference.release()
        return True

    def _finish(self) -> ErrorResult:
        reference = self.reference.radiance()
        lpv = np.asarray(self.frame.indirect, np.float32)
        valid = np.asarray(self.reference.gbuffer.valid, bool)
        stats = error_stats(lpv, reference, valid)
        image = error_image(lpv, reference, valid, "log2-ratio", LOG2_SCALE)
        return ErrorResult(self.settings, self.measurement, lpv, reference, valid, stats,
                           image)

    def release(self) -> None:
        if self.reference is not None:
            self.reference.release()
