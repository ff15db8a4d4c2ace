"""The scene's triangles and base-colour textures on the GPU, shared by the RSM and
G-buffer passes. Moving an object rewrites only that object's corners
(:meth:`SceneBuffers.show`).

Every draw binds a base-colour texture at :data:`BASE_COLOUR_UNIT` (a 1×1 white one for
untextured triangles, so the shaders multiply the vertex albedo by the texture always and
an untextured surface's albedo is its vertex albedo bit for bit: times 1.0) and says whether the
triangles are one-sided (``u_one_sided``, shaders/surface.glsl). The scene's triangles are
drawn in runs that share both (:meth:`Scene.draw_runs`); a program that numbers triangles
(``gl_PrimitiveID``, which restarts at every draw) adds ``u_first_triangle``.
"""

from __future__ import annotations

import moderngl
import numpy as np

from explorer.gl.program import set_uniform
from explorer.scene.model import Scene

VERTEX_FORMAT = ("3f 3f 3f 2f", "in_position", "in_normal", "in_albedo", "in_uv")
VERTEX_BYTES = 44
"""Bytes of one corner: position, normal, albedo (three float32 each), uv (two)."""
BASE_COLOUR_UNIT = 0
"""The texture unit of ``u_base_colour`` (the scene passes bind no other texture)."""


class SceneBuffers:
    """One vertex buffer of interleaved position, normal, albedo, uv; the scene's textures
    with their mipmaps; a vertex array per program that draws it."""

    def __init__(self, ctx: moderngl.Context, scene: Scene) -> None:
        self.ctx = ctx
        self.scene = scene
        self.vertex_count = len(scene.positions)
        self.buffer = ctx.buffer(scene.vertex_bytes())
        self._arrays: dict[int, moderngl.VertexArray] = {}
        self._uniforms: dict[int, tuple[str, ...]] = {}
        """Per program (as ``_arrays``): which of the draw's uniforms it uses."""
        self._pose = dict(scene.pose)
        self.runs = scene.draw_runs()
        self.white = _texture(ctx, np.ones((1, 1, 3), np.float32))
        self.textures = [_texture(ctx, image) for image in scene.textures]

    def show(self, scene: Scene) -> int:
        """Make the buffer hold ``scene``'s corners: ``scene`` is the buffer's scene posed
        (``Scene.posed``) another way, and only the objects whose transform changed are
        written again. Returns the number of corners written."""
        if len(scene.positions) != self.vertex_count:
            raise ValueError(f"scene {scene.name!r} has {len(scene.positions)} corners, the "
                             f"buffer {self.vertex_count}: make new SceneBuffers for it")
        pose = dict(scene.pose)
        written = 0
        for obj in scene.objects:
            if pose.get(obj.name) != self._pose.get(obj.name):
                self.buffer.write(scene.vertex_bytes(obj.first, obj.stop),
                                  offset=obj.first * VERTEX_BYTES)
                written += obj.count
        self._pose = pose
        self.scene = scene
        return written

    def draw(self, program: moderngl.Program) -> None:
        """Draw every triangle with ``program``: one call per run of triangles sharing a
        texture and a sidedness, each with its texture bound and ``u_one_sided`` set."""
        vertex_array = self._vertex_array(program)
        used = self._uniforms[id(program)]
        # a program from the loader (explorer/gl/program.py) keeps what was uploaded: a
        # value it holds already is not uploaded again (the same every frame)
        upload = set_uniform if isinstance(getattr(program, "extra", None), dict) and \
            "declared" in program.extra else _upload
        for first, count, texture, one_sided in self.runs:
            if "u_base_colour" in used:
                (self.textures[texture] if texture >= 0 else self.white).use(BASE_COLOUR_UNIT)
                upload(program, "u_base_colour", BASE_COLOUR_UNIT)
            if "u_one_sided" in used:
                upload(program, "u_one_sided", int(one_sided))
            if "u_first_triangle" in used:
                upload(program, "u_first_triangle", first // 3)
            vertex_array.render(moderngl.TRIANGLES, vertices=count, first=first)

    def _vertex_array(self, program: moderngl.Program) -> moderngl.VertexArray:
        key = id(program)
        vertex_array = self._arrays.get(key)
        if vertex_array is None or vertex_array.program is not program:
            self._drop_released()
            # attributes a program does not use are optimised away: skip them with "x"
            layout_of, *names = VERTEX_FORMAT
            sizes = [int(part[:-1]) for part in layout_of.split()]
            kept = [name if name in program else None for name in names]
            layout = " ".join(f"{size}f" if name else f"{4 * size}x"
                              for name, size in zip(kept, sizes))
            vertex_array = self.ctx.vertex_array(
                program, [(self.buffer, layout, *[n for n in kept if n])])
            self._arrays[key] = vertex_array
            # ``in`` walks a moderngl program's members: asked once per program
            self._uniforms[key] = tuple(name for name in DRAW_UNIFORMS if name in program)
        return vertex_array

    def _drop_released(self) -> None:
        """Release the vertex arrays of programs released since (a program cache let go
        of them, ``explorer.gl.program.PROGRAM_CAPACITY``): they would never be drawn."""
        for key, vertex_array in list(self._arrays.items()):
            if isinstance(vertex_array.program.mglo, moderngl.InvalidObject):
                self._arrays.pop(key).release()
                self._uniforms.pop(key, None)

    def release(self) -> None:
        for vertex_array in self._arrays.values():
            vertex_array.release()
        self._arrays.clear()
        self._uniforms.clear()
        self.buffer.release()
        for texture in (self.white, *self.textures):
            texture.release()
        self.textures = []


DRAW_UNIFORMS = ("u_base_colour", "u_one_sided", "u_first_triangle")
"""The uniforms :meth:`SceneBuffers.draw` sets, on the programs that use them."""


def _upload(program, name: str, value: int) -> None:
    """A program not from the loader: uploaded every draw (nothing kept to compare)."""
    program[name].value = value


def _texture(ctx: moderngl.Context, image: np.ndarray) -> moderngl.Texture:
    """A linear float32 RGB image (row 0 at the top) as a mipmapped texture: trilinear
    minification (the levels of :func:`mip_levels`), bilinear magnification, repeating
    edges (glTF's default sampler). No anisotropic filtering: it averages several taps,
    so a constant texture sampled at texel centres would no longer return its value bit
    for bit, and the RSM's flux with it would not be exactly the untextured one
    (tests/scene/test_textures.py)."""
    height, width = image.shape[:2]
    level = np.asarray(image, np.float32)[::-1]                       # GL row 0: bottom
    texture = ctx.texture((width, height), 3, np.ascontiguousarray(level).tobytes(),
                          dtype="f4")
    texture.build_mipmaps()          # allocates the levels; their texels are written here
    for index, smaller in enumerate(mip_levels(level)[1:], 1):
        texture.write(np.ascontiguousarray(smaller).tobytes(), level=index)
    texture.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
    texture.repeat_x = texture.repeat_y = True
    return texture


def mip_levels(image: np.ndarray) -> list[np.ndarray]:
    """The mip chain of a float32 (H, W, 3) image down to 1×1, GL's sizes (each level
    ``max(1, n // 2)`` per axis): each texel the mean, in float64, of the 2 × 2 texels
    above it (of 3 on the last row or column of an odd size). Made here rather than by
    ``glGenerateMipmap`` so that a texel of a constant region is that constant bit for
    bit at every level (the driver's float average of four texels can miss it by a unit
    in the last place), and a level's mean is the image's."""
    levels = [np.asarray(image, np.float32)]
    while levels[-1].shape[0] > 1 or levels[-1].shape[1] > 1:
        above = levels[-1].astype(np.float64)
        levels.append(_halved(_halved(above, 0), 1).astype(np.float32))
    return levels


def _halved(image: np.ndarray, axis: int) -> np.ndarray:
    """``image`` averaged in pairs along ``axis`` (a length of 1 stays; an odd length's
    last pair takes the leftover texel in as a third)."""
    count = image.shape[axis]
    if count == 1:
        return image
    half = count // 2
    pairs = np.take(image, np.arange(2 * half), axis=axis)
    shape = list(pairs.shape)
    shape[axis:axis + 1] = [half, 2]
    halved = pairs.reshape(shape).mean(axis=axis + 1)
    if count % 2:
        last = [slice(None)] * image.ndim
        last[axis] = slice(half - 1, half)
        tail = np.take(image, [count - 3, count - 2, count - 1], axis=axis).mean(
            axis=axis, keepdims=True)
        halved[tuple(last)] = tail
    return halved
