"""The slice plane: one quad through a layer of cells, each cell coloured by a scalar
(quantities.slice_field) through the colour bar's own table."""

from __future__ import annotations

import moderngl
import numpy as np

from explorer.gl.program import ProgramCache, set_uniforms
from explorer.gl.targets import scoped
from explorer.scene.transforms import gl_matrix
from explorer.ui.overlays.quantities import LOG_DECADES, colour_table
from explorer.ui.textures import to_rgba8

PROGRAM = "overlay_slice.glsl"


def colour_map_texture(ctx: moderngl.Context, name: str, linear: bool = False
                       ) -> moderngl.Texture:
    """The colour map ``name`` as a COLOUR_MAP_SIZE × 1 RGBA8 texture, bottom of the bar
    first (nearest entries, or ``linear`` interpolation between them)."""
    table = to_rgba8(colour_table(name)[None])
    texture = ctx.texture((table.shape[1], 1), 4, table.tobytes(), dtype="f1")
    smooth = moderngl.LINEAR if linear else moderngl.NEAREST
    texture.filter = (smooth, smooth)
    texture.repeat_x = texture.repeat_y = False
    return texture


class SliceRenderer:
    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self._values: moderngl.Texture | None = None
        self._maps: dict[str, moderngl.Texture] = {}
        self._vertex_array: moderngl.VertexArray | None = None

    def upload(self, values: np.ndarray) -> None:
        """The layer's values, ``values[i, j]`` = cell i along the plane's u axis, j along
        v (quantities.slice_values); one R32F texel per cell."""
        values = np.asarray(values, np.float32)
        size = (values.shape[0], values.shape[1])
        if self._values is None or self._values.size != size:
            if self._values is not None:
                self._values.release()
            self._values = self.ctx.texture(size, 1, dtype="f4")
            self._values.filter = (moderngl.NEAREST, moderngl.NEAREST)
        # a texture's rows run along its second index: row j holds the cells (·, j)
        self._values.write(np.ascontiguousarray(values.T).tobytes())

    def _colour_map(self, name: str) -> moderngl.Texture:
        texture = self._maps.get(name)
        if texture is None:
            texture = self._maps[name] = colour_map_texture(self.ctx, name)
        return texture

    def draw(self, target: moderngl.Framebuffer, view_projection: np.ndarray, corner,
             edge_u, edge_v, low: float, high: float, colour_map: str, opacity: float,
             on_top: bool, log: bool = False) -> None:
        """Blend the quad over ``target``: depth-tested against what is there (not
        written), or over everything with ``on_top``."""
        if self._values is None:
            return
        program = self.programs.get(PROGRAM)
        if self._vertex_array is None or self._vertex_array.program is not program:
            if self._vertex_array is not None:
                self._vertex_array.release()
            self._vertex_array = self.ctx.vertex_array(program, [])
        self._values.use(0)
        self._colour_map(colour_map).use(1)
        set_uniforms(program, {
            "u_view_projection": gl_matrix(view_projection),
            "u_corner": tuple(map(float, corner)), "u_edge_u": tuple(map(float, edge_u)),
            "u_edge_v": tuple(map(float, edge_v)), "u_values": 0, "u_colour_map": 1,
            "u_low": float(low), "u_high": float(high), "u_opacity": float(opacity),
            "u_log": int(log), "u_decades": LOG_DECADES})
        flags = moderngl.BLEND | (moderngl.NOTHING if on_top else moderngl.DEPTH_TEST)
        with scoped(self.ctx, target, flags):
            self.ctx.blend_func = moderngl.DEFAULT_BLENDING
            target.depth_mask = False
            try:
                self._vertex_array.render(moderngl.TRIANGLE_STRIP, vertices=4)
            finally:
                target.depth_mask = True

    def release(self) -> None:
        for texture in [self._values, *self._maps.values()]:
            if texture is not None:
                texture.release()
        if self._vertex_array is not None:
            self._vertex_array.release()
        self._values, self._maps, self._vertex_array = None, {}, None
