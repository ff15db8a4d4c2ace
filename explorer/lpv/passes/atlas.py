"""The VPL atlas: several VPL texture sets (one per RSM view, docs/MODEL.md "Several
lights") copied side by side into one set, so that the injection runs once over the VPLs
of every light (additive: each VPL adds its lobe wherever it sits) and the final gather
reads every shadow map from one pair of textures.

Every set has the same size ``(W, H)`` (the RSM size, or the downsampled one): view ``k``
fills the tile whose lower-left texel is :meth:`AtlasLayout.origin` ``(k)``. Tiles go up a
column first, as many as fit below the driver's largest framebuffer, then the next
column. Texels of the atlas outside every tile are empty (``position.w = 0``: skipped by
the injection). One set needs no atlas: the pipeline uses it as it is.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import moderngl

from explorer.gl.fullscreen import FullscreenTriangle
from explorer.gl.program import ProgramCache, set_uniforms
from explorer.gl.targets import RenderTargets
from explorer.lpv.vpl import VplTextures


class PerView:
    """One pass object per RSM view (an RSM or a downsample pass: each owns the textures it
    renders, which must outlive the next view's), made on first use."""

    def __init__(self, make: Callable[[], object]) -> None:
        self._make = make
        self.passes: list = []

    def run(self, index: int, *args, **kwargs):
        """``run(*args, **kwargs)`` of view ``index``'s pass."""
        while len(self.passes) <= index:
            self.passes.append(self._make())
        return self.passes[index].run(*args, **kwargs)

    def keep(self, count: int) -> None:
        """Release the passes of views from ``count`` on (the lights now have fewer views:
        a point light's six faces, each RSM's 4 targets, stayed after it went)."""
        for entry in self.passes[count:]:
            entry.release()
        del self.passes[count:]

    def release(self) -> None:
        self.keep(0)


@dataclass(frozen=True)
class AtlasLayout:
    """Where ``count`` tiles of ``tile`` (width, height) texels sit in the atlas."""

    count: int
    tile: tuple[int, int]
    rows: int
    """Tiles per column."""

    @classmethod
    def fit(cls, count: int, tile: tuple[int, int], largest: int = 0) -> AtlasLayout:
        """The layout of ``count`` tiles within ``largest`` texels per side (0: no limit,
        one column); a ValueError when they do not fit."""
        width, height = (int(v) for v in tile)
        rows = count if not largest else max(1, min(count, (largest - 1) // height))
        layout = cls(int(count), (width, height), rows)
        if largest and (layout.size[0] >= largest or layout.size[1] >= largest):
            raise ValueError(f"{count} RSM views of {width}x{height} texels do not fit one "
                             f"atlas below this driver's largest framebuffer size {largest}: "
                             f"use a smaller rsm_size or fewer lights")
        return layout

    @property
    def columns(self) -> int:
        return -(-self.count // self.rows)

    @property
    def size(self) -> tuple[int, int]:
        """(width, height) of the atlas in texels."""
        return self.columns * self.tile[0], self.rows * self.tile[1]

    def origin(self, index: int) -> tuple[int, int]:
        """Lower-left texel (x, y) of tile ``index`` (GL order: row 0 at the bottom)."""
        if not 0 <= index < self.count:
            raise IndexError(f"tile {index} outside 0..{self.count - 1}")
        return (index // self.rows) * self.tile[0], (index % self.rows) * self.tile[1]


class VplAtlas:
    """Copies VPL texture sets into one atlas of four ``rgba32f`` textures (position,
    normal, flux, albedo), owned by this object."""

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self._targets = RenderTargets(ctx, ("f4",) * 4)
        self._targets.keep_sizes = 0        # follows the views' count and the RSM's size
        self._triangle = FullscreenTriangle(ctx)
        self.layout: AtlasLayout | None = None

    def build(self, sets: list[VplTextures], largest: int = 0) -> VplTextures:
        """The atlas of ``sets`` (all of one size); its ``texel_area`` and ``projection``
        are the first set's (the injection and the shadow lookups read neither), and it
        stays valid until the next :meth:`build` or :meth:`release`."""
        sizes = {tuple(vpls.size) for vpls in sets}
        if len(sizes) != 1:
            raise ValueError(f"the VPL sets of an atlas must have one size, got {sorted(sizes)}")
        layout = AtlasLayout.fit(len(sets), sizes.pop(), largest)
        self._targets.allocate(layout.size)
        program = self.programs.get("vpl_atlas.glsl")
        with self._targets.drawing(clear=True) as framebuffer:
            for index, vpls in enumerate(sets):
                origin = layout.origin(index)
                framebuffer.viewport = (*origin, *layout.tile)
                textures = (vpls.position, vpls.normal, vpls.flux,
                            vpls.albedo if vpls.albedo is not None else vpls.flux)
                for unit, texture in enumerate(textures):
                    texture.use(unit)
                set_uniforms(program, {
                    "u_source_position": 0, "u_source_normal": 1, "u_source_flux": 2,
                    "u_source_albedo": 3, "u_has_albedo": int(vpls.albedo is not None),
                    "u_tile_origin": origin})
                self._triangle.draw(program)
        self.layout = layout
        position, normal, flux, albedo = self._targets.textures
        return VplTextures(position, normal, flux, texel_area=sets[0].texel_area,
                           projection=sets[0].projection, albedo=albedo)

    def release_targets(self) -> None:
        """Release the atlas's textures (one set needs no atlas); the next :meth:`build`
        makes them anew."""
        self._targets.release()
        self.layout = None

    def release(self) -> None:
        self.release_targets()
        self._triangle.release()
