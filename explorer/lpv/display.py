"""The final image as shown: the display pass (docs/MODEL.md "Display").

A full-screen pass reads the gather's linear ``final`` texture (``exposure·(direct +
indirect)``) and writes the ``rgba8`` display texture the window shows: each pixel scaled
by the display scale (the auto exposure ``key/L̄``, or 1), put through the tone curve and
sRGB-encoded, with ``display_encode`` of shaders/tonemap.glsl. The scale and the curve
have a numpy twin in :mod:`explorer.lpv.tonemap` (``render_view("final")`` uses it for
PNGs).
"""

from __future__ import annotations

import moderngl
import numpy as np

from explorer.gl.fullscreen import FullscreenTriangle
from explorer.gl.program import ProgramCache, set_uniforms
from explorer.lpv.tonemap import auto_exposure_scale, tone_map_index


def display_scale(unexposed: np.ndarray, mask: np.ndarray | None, auto_exposure: bool
                  ) -> float:
    """The display scale of a frame: ``key/L̄`` of its unexposed image over the pixels
    that show a surface (``mask``) with auto exposure, else 1. The image must be the one
    shown before the exposure (``direct + indirect``, or ``indirect`` alone), so that the
    exposure still acts as a compensation on top of the auto exposure."""
    return auto_exposure_scale(unexposed, mask) if auto_exposure else 1.0


class DisplayPass:
    """Writes :attr:`texture` (``rgba8``, sRGB-encoded, linear filtering for display)."""

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self.texture: moderngl.Texture | None = None
        self._framebuffer: moderngl.Framebuffer | None = None
        self._triangle = FullscreenTriangle(ctx)

    def _allocate(self, size: tuple[int, int]) -> None:
        if self.texture is not None and self.texture.size == size:
            return
        self._free()
        self.texture = self.ctx.texture(size, 4, dtype="f1")
        self.texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
        self._framebuffer = self.ctx.framebuffer([self.texture])

    def run(self, final: moderngl.Texture, scale: float, tone_map: str) -> moderngl.Texture:
        """Encode ``final`` (linear ``rgba32f``) for display; returns :attr:`texture`."""
        self._allocate(final.size)
        program = self.programs.get("display.glsl")
        final.use(0)
        set_uniforms(program, {"u_final": 0, "u_display_scale": float(scale),
                               "u_tone_map": tone_map_index(tone_map)})
        with self.ctx.scope(self._framebuffer, enable_only=moderngl.NOTHING):
            self._framebuffer.viewport = (0, 0, *final.size)
            self._triangle.draw(program)
        return self.texture

    def _free(self) -> None:
        if self._framebuffer is not None:
            self._framebuffer.release()
            self._framebuffer = None
        if self.texture is not None:
            self.texture.release()
            self.texture = None

    def release(self) -> None:
        self._free()
        self._triangle.release()
