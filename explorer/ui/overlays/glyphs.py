"""SH glyphs in the scene: one instanced draw of a unit-sphere mesh, each instance a cell
whose intensity lobe |f(ω)| the vertex shader evaluates (shaders/overlay_glyph.glsl)."""

from __future__ import annotations

import moderngl
import numpy as np

from explorer.gl.program import ProgramCache, set_uniforms
from explorer.gl.targets import scoped
from explorer.scene.transforms import gl_matrix
from explorer.ui.overlays.instanced import InstancedMesh
from explorer.ui.overlays.quantities import Glyphs, glyph_directions

PROGRAM = "overlay_glyph.glsl"


def glyph_peaks(coefficients: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """(G,) largest |f(ω)| of each glyph over the mesh's directions: the shader shades a
    glyph by |f(ω)| over it, so its strong direction reads bright and its weak side dark
    from any camera (a lobe seen head-on is otherwise a ball)."""
    from explorer.lpv.twin.light_grid import sh_basis

    values = np.asarray(coefficients, np.float64) @ sh_basis(directions, 2).T
    return np.abs(values).max(axis=1) if len(values) else np.zeros(0)


class GlyphRenderer:
    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        directions, indices = glyph_directions()
        self._mesh = InstancedMesh(ctx, programs, PROGRAM, directions, "3f", ("in_direction",),
                                   "3f 1f 4f 4f 1f 1f", ("in_centre", "in_scale", "in_sh0",
                                                         "in_sh1", "in_sh2", "in_peak"),
                                   indices)
        self._directions = directions

    def upload(self, glyphs: Glyphs) -> None:
        rows = np.concatenate([glyphs.centres, glyphs.scales[:, None], glyphs.coefficients,
                               glyph_peaks(glyphs.coefficients, self._directions)[:, None]],
                              axis=1)
        self._mesh.upload("glyphs", rows)

    @property
    def count(self) -> int:
        return self._mesh.count("glyphs")

    def draw(self, target: moderngl.Framebuffer, view_projection: np.ndarray,
             light_direction) -> None:
        """Depth-tested, opaque; ``light_direction``: unit vector the shading uses (the
        view direction reversed keeps the lobes facing the viewer bright)."""
        program = self._mesh.program()
        set_uniforms(program, {"u_view_projection": gl_matrix(view_projection),
                               "u_light_direction": tuple(map(float, light_direction))})
        with scoped(self.ctx, target, moderngl.DEPTH_TEST):
            self._mesh.render("glyphs")

    def release(self) -> None:
        self._mesh.release()
