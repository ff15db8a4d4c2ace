"""One side's picture as the window shows it: the window's own copy of the pipeline's
linear buffers (``shaders/view_snapshot.glsl``).

The pipeline rewrites its targets while a job runs (a camera move re-renders the
G-buffer before the gather, the gather runs in bands of rows, a preview gathers the
accumulation so far), so the view never reads them directly: when a frame finishes or a
progressive preview is made, the controller copies them here, and the view composes
what it shows from these copies (explorer/ui/view_composer.py) for as long as it likes.
The copies are image copies (explorer/gl/image_copy.py), no draw; the albedo the view
shows, with its geometry edges marked, is a pass of its own (``view_snapshot.glsl``
SOURCES 1) drawn from the copies when it is first read, so the frame that publishes a
picture does not pay for an edge test the final, direct and indirect views never show.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import moderngl
import numpy as np

from explorer.gl.fullscreen import FullscreenTriangle
from explorer.gl.image_copy import can_copy, copy_texture
from explorer.gl.program import ProgramCache, set_uniforms
from explorer.gl.targets import RenderTargets
from explorer.lpv.surface_edges import edge_uniforms

if TYPE_CHECKING:
    from explorer.lpv.frame import FrameResult

SNAPSHOT = "view_snapshot.glsl"


@dataclass(frozen=True)
class SideDisplay:
    """How the view shows one side's picture: the display stage's parameters
    (docs/MODEL.md "Display")."""

    exposure: float
    scale: float
    """The display scale: auto exposure key/L̄, or 1, or A's (B shown at A's exposure)."""
    tone_map: str
    indirect_only: bool


@dataclass(frozen=True)
class Stamp:
    """What a picture shows."""

    serial: int
    """Increases with every picture the side publishes (the view redraws on a new one)."""
    final: bool
    """A finished frame (else a progressive preview of the propagation)."""
    done: int = 0
    """Propagation steps in the picture (all cascades together) ..."""
    total: int = 0
    """... of this many."""
    injected: bool = False
    """A preview of the injected light alone (grid_0, before the propagation's first
    step: a partial picture, labelled so in the view)."""


class Picture:
    """Linear direct and indirect radiance (``rgba32f``) and albedo (``rgba16f``, w = 1
    on a surface, :data:`~explorer.lpv.surface_edges.EDGE_FLAG` on its geometry edges) of
    one side, row 0 at the bottom, with what they show (:attr:`stamp`) and the finished
    frame they belong to (:attr:`result`, the last finished one for a preview); for a
    frame with fog also the fog pass's two targets (:attr:`has_fog`), which the view
    composes over the surfaces as the display stage does."""

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self._radiance = RenderTargets(ctx, ("f4", "f4"))
        self._gbuffer = RenderTargets(ctx, ("f4", "f4", "f4"))
        """The G-buffer's albedo, position and normal as the last copy found them."""
        self._albedo = RenderTargets(ctx, ("f2",))
        self._albedo_due = False
        """The albedo is to be drawn from :attr:`_gbuffer` on its next read."""
        self._edges = False
        """:attr:`_gbuffer` holds the position and normal (the edges are marked)."""
        self._fog_targets = RenderTargets(ctx, ("f4", "f4"))
        self.has_fog = False
        """The picture holds fog (:attr:`fog_direct`, :attr:`fog_lpv`)."""
        self._triangle = FullscreenTriangle(ctx)
        self.stamp: Stamp | None = None
        self.result: FrameResult | None = None

    @property
    def size(self) -> tuple[int, int]:
        return self._radiance.size

    @property
    def direct(self) -> moderngl.Texture:
        return self._radiance.textures[0]

    @property
    def indirect(self) -> moderngl.Texture:
        return self._radiance.textures[1]

    @property
    def albedo(self) -> moderngl.Texture:
        """The albedo at :attr:`size`, its geometry edges marked (drawn on the first read
        after a copy, explorer/lpv/surface_edges.py)."""
        if self._albedo_due:
            self._draw_albedo()
        return self._albedo.textures[0]

    @property
    def fog_direct(self) -> moderngl.Texture:
        """The direct light's in-scattered radiance, the transmittance in w (fog.glsl)."""
        return self._fog_targets.textures[0]

    @property
    def fog_lpv(self) -> moderngl.Texture:
        """The LPV's in-scattered radiance (fog.glsl)."""
        return self._fog_targets.textures[1]

    @property
    def ready(self) -> bool:
        return self.stamp is not None

    def copy_from(self, direct: moderngl.Texture, indirect: moderngl.Texture,
                  albedo: moderngl.Texture, stamp: Stamp,
                  result: FrameResult | None,
                  fog: tuple[moderngl.Texture, moderngl.Texture] | None = None,
                  surfaces: tuple[moderngl.Texture, moderngl.Texture] | None = None
                  ) -> None:
        """Copy the pipeline's radiance (``direct`` and ``indirect``, one size), its
        ``albedo`` (that size or the G-buffer's larger one) with ``surfaces`` (the
        G-buffer's position and normal, the albedo's size, which mark the albedo's geometry
        edges) and ``fog`` (the fog pass's direct and LPV targets of a frame with fog)."""
        self._copy_pair(self._radiance, direct, indirect)
        self._gbuffer.allocate(albedo.size)
        copy_texture(albedo, self._gbuffer.textures[0])
        self._edges = surfaces is not None
        if surfaces is not None:
            for source, copy in zip(surfaces, self._gbuffer.textures[1:]):
                copy_texture(source, copy)
        self._albedo_due = True
        self.has_fog = fog is not None
        if fog is not None:
            self._copy_pair(self._fog_targets, *fog)
        self.stamp, self.result = stamp, result

    def _copy_pair(self, targets: RenderTargets, first: moderngl.Texture,
                   second: moderngl.Texture) -> None:
        """``first`` and ``second`` into ``targets`` at ``first``'s size: image copies, or
        one draw that takes the texel below each pixel of a ``second`` of another size."""
        targets.allocate(first.size)
        copies = tuple(zip((first, second), targets.textures))
        if all(can_copy(source, copy) for source, copy in copies):
            for source, copy in copies:
                copy_texture(source, copy)
            return
        program = self.programs.get(SNAPSHOT, {"SOURCES": 2, "EDGES": 0})
        first.use(0)
        second.use(1)
        set_uniforms(program, {"u_source0": 0, "u_source1": 1})
        with targets.drawing():
            self._triangle.draw(program)

    def _draw_albedo(self) -> None:
        """The albedo at :attr:`size` from the G-buffer's copies (view_snapshot.glsl
        SOURCES 1), its edges marked when the copy had the surfaces."""
        self._albedo.allocate(self.size)
        program = self.programs.get(SNAPSHOT, {"SOURCES": 1, "EDGES": int(self._edges)})
        uniforms: dict[str, object] = {"u_source0": 0, "u_size": self.size}
        self._gbuffer.textures[0].use(0)
        if self._edges:
            self._gbuffer.textures[1].use(1)
            self._gbuffer.textures[2].use(2)
            uniforms.update(u_position=1, u_normal=2, **edge_uniforms())
        set_uniforms(program, uniforms)
        with self._albedo.drawing():
            self._triangle.draw(program)
        self._albedo_due = False

    def read(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(direct, indirect, surface mask)`` as numpy, top row first: ``(H, W, 3)``
        float32 twice and ``(H, W)`` bool (the auto exposure of a first preview, which
        has no finished frame to take it from)."""
        width, height = self.size
        arrays = []
        for texture, dtype in ((self.direct, np.float32), (self.indirect, np.float32),
                               (self.albedo, np.float16)):
            data = np.frombuffer(texture.read(), dtype).reshape(height, width, 4)
            arrays.append(data[::-1])
        direct, indirect, albedo = arrays
        return direct[..., :3].copy(), indirect[..., :3].copy(), albedo[..., 3] > 0.5

    def release(self) -> None:
        for targets in (self._radiance, self._gbuffer, self._albedo, self._fog_targets):
            targets.release()
        self._albedo_due = self._edges = False
        self.has_fog = False
        self._triangle.release()
        self.stamp, self.result = None, None
