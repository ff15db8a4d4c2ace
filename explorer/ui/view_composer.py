"""What the View panel shows, composed on the GPU from the sides' pictures
(``shaders/view.glsl``): the chosen buffer of one side as the display shows it, or the
difference of A and B in false colour.

Every display-only choice is a uniform of that one pass (exposure, tone curve, indirect
only, each side's display scale, the buffer shown, the difference's scale and colour
map), so changing one draws it once and runs no stage of the pipeline; an unchanged
request draws nothing (:attr:`ViewComposer.draws` counts the draws). The split view
needs no pass at all: the panel draws the two sides' images left and right of the
divider. The overlays' compositor (explorer/ui/overlays/compositor.py) draws on top of a
side's image.
"""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from explorer.gl.context import use_screen
from explorer.gl.fullscreen import FullscreenTriangle
from explorer.gl.program import ProgramCache, set_uniforms
from explorer.gl.targets import RenderTargets
from explorer.lpv.passes.display import exposed_image
from explorer.lpv.surface_edges import EDGE_FLAG, EDGE_SHADE
from explorer.lpv.twin.tonemap import luminance, tone_map_index
from explorer.ui.picture import Picture, SideDisplay
from explorer.ui.state import VIEW_BUFFERS
from explorer.ui.texture_versions import versions_for
from explorer.ui.textures import robust_max
from explorer.ui.weak_version import WeakVersion

VIEW = "view.glsl"
DIFFERENCE_MAPS = ("heat", "diverging")
"""|A − B| on the heat map, or the signed A − B on the diverging map."""


@dataclass(frozen=True)
class Difference:
    """The difference image's texture and the value at the top of its scale bar."""

    texture: int
    top: float
    signed: bool


class _Output:
    """One RGBA8 image the view shows and the key of what it holds."""

    def __init__(self, ctx: moderngl.Context) -> None:
        self.targets = RenderTargets(ctx, ("f1",), linear=(0,))
        self.key: object = None
        self.versions = versions_for(ctx)
        self.shown: int | None = None
        """The GL name of the texture last drawn, tracked in :attr:`versions` (the window
        repaints the view only when a pass drew it anew: explorer/ui/texture_versions.py)."""

    def drawn(self) -> None:
        """A pass drew into the output's texture."""
        glo = self.targets.textures[0].glo
        if self.shown not in (None, glo):         # another size's texture: the old name
            self.versions.forget(self.shown)      # may be released and handed out again
        self.versions.written(glo)
        self.shown = glo

    def release(self) -> None:
        if self.shown is not None:
            self.versions.forget(self.shown)
            self.shown = None
        self.targets.release()
        self.key = None


class ViewComposer:
    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self._triangle = FullscreenTriangle(ctx)
        self._outputs: dict[str, _Output] = {}
        self._maps: dict[str, moderngl.Texture] = {}
        self._auto_top_cache: tuple[WeakVersion, float] | None = None
        """(the results A and B, buffer, indirect only, exposure ratio) → top: one entry,
        its results held weakly (a freed one's id names no entry; the cache keeps no
        frame alive)."""
        self.draws = 0
        """Passes drawn so far (an unchanged request draws nothing)."""

    # ------------------------------------------------------------------ entry points
    def side_image(self, side: str, picture: Picture, display: SideDisplay,
                   buffer: str) -> int:
        """The GL name of an RGBA8 texture (row 0 at the bottom) with ``buffer`` of
        ``picture`` as the display shows it (docs/MODEL.md "Display")."""
        key = ("side", id(picture), picture.stamp, picture.size, display, buffer)
        output = self._output(side)
        if output.key != key:
            self._draw(output, picture.size, 0, buffer, {
                "u_indirect_only": int(display.indirect_only),
                "u_tone_map": tone_map_index(display.tone_map),
                "u_exposure_a": display.exposure, "u_scale_a": display.scale},
                picture, None)
            output.key = key
        return output.targets.textures[0].glo

    def difference(self, a: Picture, b: Picture, display_a: SideDisplay,
                   display_b: SideDisplay, buffer: str, scale: float,
                   colour_map: str = "heat") -> Difference:
        """False-colour luminance difference of ``buffer`` (each side's exposure for
        "final", as ``FrameResult.final_image``) at ``a``'s size; ``scale``: the value at
        the top of the scale (0: the 99.5th percentile of |A − B| over the last finished
        frames of both sides)."""
        if colour_map not in DIFFERENCE_MAPS:
            raise ValueError(f"colour map must be one of {DIFFERENCE_MAPS}, got "
                             f"{colour_map!r}")
        signed = colour_map == "diverging"
        top = scale if scale > 0 else self._auto_top(a, b, display_a, display_b, buffer)
        key = ("difference", id(a), a.stamp, a.size, id(b), b.stamp, b.size, buffer,
               display_a.exposure, display_b.exposure, display_a.indirect_only, top, signed)
        output = self._output("difference")
        if output.key != key:
            self._colour_map(colour_map).use(6)
            self._draw(output, a.size, 1, buffer, {
                "u_indirect_only": int(display_a.indirect_only), "u_tone_map": 0,
                "u_exposure_a": display_a.exposure, "u_exposure_b": display_b.exposure,
                "u_scale_a": 1.0, "u_signed": int(signed), "u_top": float(top),
                "u_colour_map": 6}, a, b)
            output.key = key
        return Difference(output.targets.textures[0].glo, float(top), signed)

    def read(self, name: str) -> np.ndarray:
        """The last image of ``name`` ("A", "B" or "difference") as (H, W, 4) uint8, top
        row first (tests)."""
        texture = self._outputs[name].targets.textures[0]
        width, height = texture.size
        return np.frombuffer(texture.read(), np.uint8).reshape(height, width, 4)[::-1]

    def release(self) -> None:
        for output in self._outputs.values():
            output.release()
        self._outputs.clear()
        for texture in self._maps.values():
            texture.release()
        self._maps.clear()
        self._triangle.release()
        self._auto_top_cache = None

    # ------------------------------------------------------------------ helpers
    def _output(self, name: str) -> _Output:
        output = self._outputs.get(name)
        if output is None:
            output = self._outputs[name] = _Output(self.ctx)
        return output

    def _draw(self, output: _Output, size: tuple[int, int], mode: int, buffer: str,
              uniforms: dict, a: Picture, b: Picture | None) -> None:
        """One pass of view.glsl, its mode (0 one side, 1 difference), buffer and each
        side's fog compiled in (one program per combination, made on first use)."""
        output.targets.allocate(size)
        b_shown = b
        b = b or a
        # the fog is composed over "final" only (direct and indirect are the surfaces' own)
        fog_a = buffer == "final" and a.has_fog
        fog_b = buffer == "final" and b_shown is not None and b.has_fog
        program = self.programs.get(VIEW, {"VIEW_MODE": mode,
                                           "VIEW_BUFFER": VIEW_BUFFERS.index(buffer),
                                           "FOG_A": int(fog_a), "FOG_B": int(fog_b)})
        # the albedo is drawn from the picture's copies when first read: only for its view
        albedo = buffer == "albedo"
        textures = (a.direct, a.indirect, a.albedo if albedo else a.direct,
                    b.direct, b.indirect, b.albedo if albedo else b.direct,
                    a.fog_direct if fog_a else a.direct, a.fog_lpv if fog_a else a.direct,
                    b.fog_direct if fog_b else b.direct, b.fog_lpv if fog_b else b.direct)
        for unit, texture in zip((0, 1, 2, 3, 4, 5, 7, 8, 9, 10), textures):
            texture.use(unit)          # unit 6: the difference's colour map
        set_uniforms(program, {"u_direct_a": 0, "u_indirect_a": 1, "u_albedo_a": 2,
                               "u_direct_b": 3, "u_indirect_b": 4, "u_albedo_b": 5,
                               "u_fog_direct_a": 7, "u_fog_lpv_a": 8,
                               "u_fog_direct_b": 9, "u_fog_lpv_b": 10,
                               "u_edge_flag": EDGE_FLAG, "u_edge_shade": EDGE_SHADE,
                               **uniforms})
        with output.targets.drawing():
            self._triangle.draw(program)
        output.drawn()
        use_screen(self.ctx)
        self.draws += 1

    def _colour_map(self, name: str) -> moderngl.Texture:
        texture = self._maps.get(name)
        if texture is None:
            from explorer.ui.overlays.slice import colour_map_texture

            texture = self._maps[name] = colour_map_texture(self.ctx, name, linear=True)
        return texture

    def _auto_top(self, a: Picture, b: Picture, display_a: SideDisplay,
                  display_b: SideDisplay, buffer: str) -> float:
        """The 99.5th percentile of |ΔL| over the sides' last finished frames (cached;
        the luminance is linear, so with the same exposure on both sides it scales with
        the exposure and is measured once)."""
        ra, rb = a.result, b.result
        if ra is None or rb is None or ra.direct.shape != rb.direct.shape:
            return 1.0
        final = buffer == "final"
        ratio = display_b.exposure / display_a.exposure if final else 1.0
        wanted = (buffer, display_a.indirect_only, ratio)
        parts = (ra, rb, *wanted)
        cached = self._auto_top_cache
        if cached is None or not cached[0].matches(parts):
            la = luminance(_linear(ra, buffer, display_a.indirect_only))
            lb = luminance(_linear(rb, buffer, display_a.indirect_only))
            cached = self._auto_top_cache = (WeakVersion(parts, (str, bool, int, float)),
                                             robust_max(np.abs(la - ratio * lb)))
        return cached[1] * (display_a.exposure if final else 1.0)


def _linear(result, buffer: str, indirect_only: bool) -> np.ndarray:
    """The unexposed linear image of ``buffer`` of a finished frame (with its fog for
    "final", as the display composes it)."""
    if buffer == "final":
        return exposed_image(result.direct, result.indirect, 1.0, indirect_only, result.fog)
    return getattr(result, buffer)
