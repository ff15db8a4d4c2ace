"""G-buffer from the camera: world position, normal (w = pixel's world area), albedo."""

from __future__ import annotations

import moderngl

from explorer.gl.program import ProgramCache, set_uniforms
from explorer.gl.targets import RenderTargets
from explorer.scene.gpu import SceneBuffers
from explorer.scene.model import Scene
from explorer.scene.transforms import gl_matrix

TARGETS = ("position", "normal", "albedo")
"""The ``rgba32f`` textures the G-buffer renders, in :attr:`GBufferPass.textures` order."""


class GBufferPass:
    """Renders the camera's view of the scene into three ``rgba32f`` textures."""

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self._targets = RenderTargets(ctx, ("f4",) * len(TARGETS), depth=True,
                                      enable=moderngl.DEPTH_TEST)
        self._uniforms: tuple[Scene, tuple[int, int], dict[str, object]] | None = None
        """The scene (frozen) and size of the last run and their camera uniforms: the same
        dict while they are the same, which ``set_uniforms`` skips as unchanged."""

    @property
    def size(self) -> tuple[int, int]:
        return self._targets.size

    @property
    def textures(self) -> list[moderngl.Texture]:
        return self._targets.textures

    @property
    def position(self) -> moderngl.Texture:
        return self.textures[0]

    @property
    def normal(self) -> moderngl.Texture:
        return self.textures[1]

    @property
    def albedo(self) -> moderngl.Texture:
        return self.textures[2]

    def run(self, geometry: SceneBuffers, scene: Scene, size: tuple[int, int]) -> None:
        self._targets.allocate(size)
        program = self.programs.get("gbuffer.glsl")
        kept = self._uniforms
        if kept is None or kept[0] is not scene or kept[1] != size:
            kept = self._uniforms = (scene, size, camera_uniforms(scene, size))
        set_uniforms(program, kept[2])
        with self._targets.drawing(clear=True):
            geometry.draw(program)

    def release(self) -> None:
        self._targets.release()


def camera_uniforms(scene: Scene, size: tuple[int, int]) -> dict[str, object]:
    """``u_view`` and ``u_projection`` of ``scene``'s camera for an image of ``size``: the
    G-buffer's, and of every pass that must see exactly its pixels (the surface masks'
    triangle ids, explorer/truth/surface_masks.py)."""
    width, height = size
    camera = scene.camera
    return {"u_view": gl_matrix(camera.view_matrix()),
            "u_projection": gl_matrix(camera.projection_matrix(
                width / height, scene.bounds_min, scene.bounds_max))}
