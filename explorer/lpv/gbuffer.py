"""G-buffer from the camera: world position, normal (w = pixel's world area), albedo."""

from __future__ import annotations

import moderngl

from explorer.gl.program import ProgramCache, set_uniforms
from explorer.scene.gpu import SceneBuffers
from explorer.scene.model import Scene
from explorer.scene.transforms import gl_matrix


class GBufferPass:
    """Renders the camera's view of the scene into three ``rgba32f`` textures."""

    def __init__(self, ctx: moderngl.Context, programs: ProgramCache) -> None:
        self.ctx = ctx
        self.programs = programs
        self.size: tuple[int, int] = (0, 0)
        self.textures: list[moderngl.Texture] = []
        self._depth: moderngl.Renderbuffer | None = None
        self._framebuffer: moderngl.Framebuffer | None = None

    @property
    def position(self) -> moderngl.Texture:
        return self.textures[0]

    @property
    def normal(self) -> moderngl.Texture:
        return self.textures[1]

    @property
    def albedo(self) -> moderngl.Texture:
        return self.textures[2]

    def _allocate(self, size: tuple[int, int]) -> None:
        if size == self.size:
            return
        self.release()
        self.textures = [self.ctx.texture(size, 4, dtype="f4") for _ in range(3)]
        for texture in self.textures:
            texture.filter = (moderngl.NEAREST, moderngl.NEAREST)
        self._depth = self.ctx.depth_renderbuffer(size)
        self._framebuffer = self.ctx.framebuffer(self.textures, self._depth)
        self.size = size

    def run(self, geometry: SceneBuffers, scene: Scene, size: tuple[int, int]) -> None:
        self._allocate(size)
        width, height = size
        camera = scene.camera
        program = self.programs.get("gbuffer.glsl")
        set_uniforms(program, {
            "u_view": gl_matrix(camera.view_matrix()),
            "u_projection": gl_matrix(camera.projection_matrix(
                width / height, scene.bounds_min, scene.bounds_max)),
        })
        with self.ctx.scope(self._framebuffer, enable_only=moderngl.DEPTH_TEST):
            self._framebuffer.viewport = (0, 0, width, height)
            self._framebuffer.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
            geometry.draw(program)

    def release(self) -> None:
        if self._framebuffer is not None:
            self._framebuffer.release()
            self._depth.release()
        for texture in self.textures:
            texture.release()
        self.textures, self._framebuffer, self._depth, self.size = [], None, None, (0, 0)
