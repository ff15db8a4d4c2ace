"""The display stage: the frame as shown (``shaders/display.glsl``, docs/MODEL.md
"Display").

A full-screen pass reads the gather's linear direct and indirect radiance and writes the
``rgba8`` texture the window shows: ``exposure·(direct + indirect)`` (``exposure·indirect``
with ``indirect_only``; with fog the surfaces seen through the medium plus its
in-scattering, docs/MODEL.md "Fog") times the display scale (the auto exposure ``key/L̄``, or 1),
through the tone curve and the sRGB encoding (``display_encode`` of shaders/tonemap.glsl).
It reads only the Settings fields declared for the ``display`` stage, so changing the
exposure, the tone curve, the auto exposure or what is shown runs this pass and no other.
The numpy twin: :func:`exposed_image` followed by
:func:`explorer.lpv.twin.tonemap.display_encode` (``render_view("final")`` uses it for PNGs).
"""

from __future__ import annotations

from collections.abc import Generator

import moderngl
import numpy as np

from explorer.gl.fullscreen import FullscreenTriangle
from explorer.gl.program import ProgramCache, set_uniforms
from explorer.gl.targets import RenderTargets
from explorer.lpv.passes.fog import FogImages
from explorer.lpv.passes.gather import GatherImages
from explorer.lpv.twin.tonemap import (
    auto_exposure_scale,
    exposure_for,
    log_average_of,
    metered_luminance,
    tone_map_index,
)


def exposed_image(direct: np.ndarray, indirect: np.ndarray, exposure: float,
                  indirect_only: bool, fog: FogImages | None = None) -> np.ndarray:
    """The linear colour the display encodes (numpy twin of display.glsl's ``exposed``):
    ``exposure·(direct + indirect)``, or ``exposure·indirect`` with ``indirect_only``;
    with ``fog`` the surfaces are seen through the medium, ``T·surface + in-scattering``
    (the LPV's in-scattering only, with ``indirect_only``)."""
    linear = indirect if indirect_only else direct + indirect
    if fog is not None:
        linear = fog.transmittance[..., None] * linear + fog.lpv
        if not indirect_only:
            linear = linear + fog.direct
    if exposure == 1.0 and linear is not indirect:
        # x·1 is x, bit for bit: the auto exposure's unexposed image skips a pass over it
        return linear.astype(np.float32, copy=False)
    return (np.float32(exposure) * linear).astype(np.float32, copy=False)


def display_scale(unexposed: np.ndarray, mask: np.ndarray | None, auto_exposure: bool
                  ) -> float:
    """The display scale of a frame: ``key/L̄`` of its unexposed image over the pixels
    that show a surface (``mask``) with auto exposure, else 1. The image must be the one
    shown before the exposure (``direct + indirect``, or ``indirect`` alone), so that the
    exposure still acts as a compensation on top of the auto exposure."""
    return auto_exposure_scale(unexposed, mask) if auto_exposure else 1.0


METER_BAND_BYTES = 1 << 19
"""The largest temporary of a band of :func:`metered_in_bands` (its rows' RGBA luminance
input in float64) at most: half the window's fixed mmap threshold (explorer/ui/memory.py,
1 MiB), so that each band's blocks come from malloc's heap and are reused by the next band.
Whole-frame temporaries are mapped afresh and their pages faulted in: the 960×540 frame's
metering took 30–54 ms in the window in one piece, 7 ms alone (BENCHMARKS.md, issue #32)."""


def metered_in_bands(gather: GatherImages, fog: FogImages | None, indirect_only: bool,
                     mask: np.ndarray) -> np.ndarray:
    """:func:`metered_luminance` of the unexposed image (``direct + indirect``, or
    ``indirect`` alone, seen through ``fog``) over ``mask``'s pixels, computed in bands of
    rows (:data:`METER_BAND_BYTES`): the same values in the same order as in one piece,
    since every step is per pixel and the mask keeps the rows' order."""
    height, width = mask.shape
    rows = max(1, METER_BAND_BYTES // (width * 4 * 8))
    parts = []
    for top in range(0, height, rows):
        band = slice(top, top + rows)
        if fog is None:
            # exposed_image's values without its strided passes: direct + indirect added
            # as whole pixels (the same float32 sums; x·1 is x), whose rgb the luminance
            # reads in float64 (twin/tonemap.py: the same bits)
            unexposed = gather.indirect[band] if indirect_only \
                else gather.direct[band] + gather.indirect[band]
        else:
            unexposed = exposed_image(gather.direct[band, :, :3], gather.indirect[band, :, :3],
                                      1.0, indirect_only, fog.part(band))
        parts.append(metered_luminance(unexposed, mask[band]))
    return np.concatenate(parts) if parts else np.zeros(0)


class AutoExposure:
    """The auto exposure scale of the frame last gathered, measured once per gathered
    frame, fog and ``indirect_only`` (an exposure change reuses it). The images are told
    apart by identity: each completed gather or fog stage reads back new arrays."""

    def __init__(self) -> None:
        self._measured: tuple[GatherImages, FogImages | None, bool, float] | None = None
        """(the gathered arrays, the fog's, indirect_only, their scale)."""

    def scale(self, gather: GatherImages, fog: FogImages | None,
              indirect_only: bool, position: np.ndarray) -> float:
        """:func:`display_scale` of the unexposed image of ``gather``'s ``direct`` and
        ``indirect`` (and ``fog``) over the pixels whose G-buffer ``position`` shows a
        surface (w = 1)."""
        measuring = self.measure(gather, fog, indirect_only, position)
        while True:
            try:
                next(measuring)
            except StopIteration as done:
                return done.value

    def measure(self, gather: GatherImages, fog: FogImages | None, indirect_only: bool,
                position: np.ndarray) -> Generator[None, None, float]:
        """:meth:`scale` in two units (``yield from`` returns it): the metered luminances,
        then their log average (each about as long at 960×540); one unit when measured
        already."""
        measured = self._measured
        if measured is None or measured[0] is not gather or measured[1] is not fog or \
                measured[2] != indirect_only:
            metered = metered_in_bands(gather, fog, indirect_only, position[..., 3] > 0.5)
            yield
            measured = self._measured = (gather, fog, indirect_only,
                                         exposure_for(log_average_of(metered)))
        return measured[3]


class DisplayPass:
    """Writes :attr:`texture`: ``rgba8``, sRGB-encoded, linear filtering for display; row
    0 is the bottom row, as OpenGL draws it."""

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self._targets = RenderTargets(ctx, ("f1",), linear=(0,))
        self._triangle = FullscreenTriangle(ctx)

    @property
    def texture(self) -> moderngl.Texture | None:
        """The display texture of the last run (None before the first)."""
        return self._targets.textures[0] if self._targets.textures else None

    def run(self, direct: moderngl.Texture, indirect: moderngl.Texture, exposure: float,
            indirect_only: bool, tone_map: str = "linear-clip",
            scale: float = 1.0,
            fog: tuple[moderngl.Texture, moderngl.Texture] | None = None
            ) -> moderngl.Texture:
        """Expose, tone-map and encode the linear ``direct`` and ``indirect`` textures
        (same size); ``scale``: the display scale (auto exposure) on top of ``exposure``;
        ``fog``: the fog pass's (direct + transmittance, LPV) targets to compose. The
        defaults show the exposed colour clipped to [0, 1]."""
        self._targets.allocate(direct.size)
        program = self.programs.get("display.glsl")
        direct.use(0)
        indirect.use(1)
        fog_direct, fog_lpv = fog if fog is not None else (direct, indirect)
        fog_direct.use(2)
        fog_lpv.use(3)
        set_uniforms(program, {"u_direct": 0, "u_indirect": 1, "u_exposure": float(exposure),
                               "u_indirect_only": int(indirect_only),
                               "u_display_scale": float(scale),
                               "u_tone_map": tone_map_index(tone_map),
                               "u_fog": int(fog is not None), "u_fog_direct": 2,
                               "u_fog_lpv": 3})
        with self._targets.drawing():
            self._triangle.draw(program)
        return self.texture

    def release(self) -> None:
        self._targets.release()
        self._triangle.release()
