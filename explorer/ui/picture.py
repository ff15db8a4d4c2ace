"""One side's picture as the window shows it: the window's own copy of the pipeline's
linear buffers (``shaders/view_snapshot.glsl``).

The pipeline rewrites its targets while a job runs (a camera move re-renders the
G-buffer before the gather, the gather runs in bands of rows, a preview gathers the
accumulation so far), so the view never reads them directly: when a frame finishes or a
progressive preview is made, the controller copies them here in one draw, and the view
composes what it shows from these copies (explorer/ui/view_composer.py) for as long as
it likes.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import moderngl
import numpy as np

from explorer.gl.fullscreen import FullscreenTriangle
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


class Picture:
    """Linear direct and indirect radiance (``rgba32f``) and albedo (``rgba16f``, w = 1
    on a surface) of one side, row 0 at the bottom, with what they show (:attr:`stamp`)
    and the finished frame they belong to (:attr:`result`, the last finished one for a
    preview); for a frame with fog also the fog pass's two targets (:attr:`has_fog`),
    which the view composes over the surfaces as the display stage does."""

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self._targets = RenderTargets(ctx, ("f4", "f4", "f2"))
        self._fog_targets = RenderTargets(ctx, ("f4", "f4"))
        self.has_fog = False
        """The picture holds fog (:attr:`fog_direct`, :attr:`fog_lpv`)."""
        self._triangle = FullscreenTriangle(ctx)
        self.stamp: Stamp | None = None
        self.result: FrameResult | None = None

    @property
    def size(self) -> tuple[int, int]:
        return self._targets.size

    @property
    def direct(self) -> moderngl.Texture:
        return self._targets.textures[0]

    @property
    def indirect(self) -> moderngl.Texture:
        return self._targets.textures[1]

    @property
    def albedo(self) -> moderngl.Texture:
        return self._targets.textures[2]

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
        """Copy the pipeline's textures (all the same size) in one draw, and ``fog`` (the
        fog pass's direct and LPV targets of a frame with fog) in a second; ``surfaces``
        (the G-buffer's position and normal, the albedo's size) mark the albedo copy's
        geometry edges (explorer/lpv/surface_edges.py)."""
        self._copy(self._targets, (direct, indirect, albedo), surfaces)
        self.has_fog = fog is not None
        if fog is not None:
            self._copy(self._fog_targets, fog)
        self.stamp, self.result = stamp, result

    def _copy(self, targets: RenderTargets, sources, surfaces=None) -> None:
        targets.allocate(sources[0].size)
        program = self.programs.get(SNAPSHOT, {"SOURCES": len(sources),
                                               "EDGES": int(surfaces is not None)})
        for unit, texture in enumerate(sources):
            texture.use(unit)
        uniforms = {f"u_source{unit}": unit for unit in range(len(sources))}
        if surfaces is not None:
            for unit, texture in enumerate(surfaces, len(sources)):
                texture.use(unit)
            uniforms.update(u_position=len(sources), u_normal=len(sources) + 1,
                            **edge_uniforms())
        set_uniforms(program, uniforms)
        with targets.drawing():
            self._triangle.draw(program)

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
        self._targets.release()
        self._fog_targets.release()
        self.has_fog = False
        self._triangle.release()
        self.stamp, self.result = None, None
