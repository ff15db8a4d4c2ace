"""The reference for a Pipeline frame: same G-buffer pixels, same VPLs, same grid."""

from __future__ import annotations

import numpy as np

from explorer.lpv.vpl import VplArrays
from explorer.truth.gbuffer import gbuffer_from_frame, scene_for, scene_triangles
from explorer.truth.reference import (
    GBuffer,
    ProgressCallback,
    ReferencePass,
    outgoing_radiance,
)


def lit_vpls(vpls: VplArrays) -> VplArrays:
    """The VPLs that carry flux: a VPL with zero flux adds exactly zero to the sum, and an
    RSM has many (texels facing away from the light), so dropping them is free speed."""
    keep = np.asarray(vpls.flux).sum(axis=1) > 0
    return VplArrays(np.asarray(vpls.positions)[keep], np.asarray(vpls.normals)[keep],
                     np.asarray(vpls.flux)[keep], np.asarray(vpls.depth)[keep],
                     vpls.texel_area, vpls.projection)


def reference_indirect(frame, visibility: bool, min_distance: float | None = None,
                       ray_offset: float | None = None, tile_size: int = 64,
                       vpl_chunk: int = 4096, progress: ProgressCallback | None = None,
                       ctx=None, scene=None) -> np.ndarray:
    """One-bounce indirect radiance (H, W, 3) float32 for a FrameResult, in the units of
    ``frame.indirect``.

    ``visibility`` False: the unoccluded sum (what LPV without a geometry volume
    approximates); True: every VPL-pixel pair is tested with a shadow ray against the
    scene's triangles. ``min_distance`` (the 1/r² clamp) defaults to half a cell of the
    frame's grid. ``progress`` gets the fraction done after each dispatch; returning
    False raises :class:`~explorer.truth.reference.Cancelled`.
    """
    radiance, _ = reference_for_frame(frame, visibility, min_distance, ray_offset, tile_size,
                                      vpl_chunk, progress, ctx, scene)
    return radiance


def reference_for_frame(frame, visibility: bool, min_distance: float | None = None,
                        ray_offset: float | None = None, tile_size: int = 64,
                        vpl_chunk: int = 4096, progress: ProgressCallback | None = None,
                        ctx=None, scene=None) -> tuple[np.ndarray, GBuffer]:
    """:func:`reference_indirect` and the G-buffer it gathered at (its ``valid`` mask is
    the region where the comparison means something)."""
    if min_distance is None:
        min_distance = 0.5 * frame.grid_spec.cell_size
    from explorer.gl.context import given_or_headless

    with given_or_headless(ctx) as ctx:
        if scene is None and (visibility or frame.gbuffer_position is None):
            scene = scene_for(frame.settings)
        gbuffer = gbuffer_from_frame(frame, scene, ctx)
        triangles = scene_triangles(scene) if visibility else None
        vpls = lit_vpls(frame.vpls)
        reference = ReferencePass(ctx)
        try:
            irradiance = reference.run(gbuffer, vpls, min_distance, triangles, visibility,
                                       ray_offset, tile_size, vpl_chunk, progress)
        finally:
            reference.release()
    return outgoing_radiance(gbuffer, irradiance), gbuffer
