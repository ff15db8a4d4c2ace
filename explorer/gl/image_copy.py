"""Texel-for-texel copies of one texture into another on the GPU (``glCopyImageSubData``,
GL 4.3), with no draw: no program, no framebuffer and no rasterisation, so on a software
renderer a copy costs about a memory copy where a full-screen pass costs a shader run per
pixel. moderngl 5 has no such call, so it goes through explorer/gl/gpu_sync.py's entry
points; it touches no state moderngl caches.
"""

from __future__ import annotations

import moderngl

from explorer.gl import gpu_sync

GL_TEXTURE_2D = 0x0DE1
GL_TEXTURE_3D = 0x806F
GL_TEXTURE_2D_ARRAY = 0x8C1A

_COPYABLE = {("f4", 4), ("f2", 4), ("f1", 4)}
"""(dtype, components) of textures this module copies (rgba32f, rgba16f, rgba8)."""


def can_copy(source: moderngl.Texture, destination: moderngl.Texture) -> bool:
    """Whether :func:`copy_texture` takes these two: one size, one format, one that
    this module knows."""
    return (source.size == destination.size and source.dtype == destination.dtype
            and source.components == destination.components
            and (source.dtype, source.components) in _COPYABLE)


def copy_texture(source: moderngl.Texture, destination: moderngl.Texture) -> None:
    """Copy level 0 of ``source`` into ``destination`` (queued, as a draw is)."""
    if not can_copy(source, destination):
        raise ValueError(f"cannot copy a {source.size} {source.dtype}x{source.components} "
                         f"texture into a {destination.size} {destination.dtype}x"
                         f"{destination.components} one")
    width, height = source.size
    gpu_sync.gl().copy_image_sub_data(source.glo, GL_TEXTURE_2D, 0, 0, 0, 0,
                                      destination.glo, GL_TEXTURE_2D, 0, 0, 0, 0,
                                      width, height, 1)


def can_copy_volume(source: moderngl.Texture3D | moderngl.TextureArray,
                    destination: moderngl.Texture3D) -> bool:
    """Whether :func:`copy_volume_texels` takes these two: a 3D texture or a 2D array
    (layer = z) and a 3D texture of one size (texels along x, y, z) and one format that
    this module knows."""
    return (isinstance(source, (moderngl.Texture3D, moderngl.TextureArray))
            and tuple(source.size) == tuple(destination.size)
            and source.dtype == destination.dtype
            and source.components == destination.components
            and (source.dtype, source.components) in _COPYABLE)


def copy_volume_texels(source: moderngl.Texture3D | moderngl.TextureArray,
                       destination: moderngl.Texture3D) -> None:
    """Copy level 0 of a 3D texture or of a 2D array's layers into the 3D texture
    ``destination``, texel for texel (queued; the bytes as they are)."""
    if not can_copy_volume(source, destination):
        raise ValueError(f"cannot copy a {source.size} {source.dtype}x{source.components} "
                         f"volume into a {destination.size} {destination.dtype}x"
                         f"{destination.components} 3D texture")
    target = GL_TEXTURE_2D_ARRAY if isinstance(source, moderngl.TextureArray) else GL_TEXTURE_3D
    width, height, depth = destination.size
    gpu_sync.gl().copy_image_sub_data(source.glo, target, 0, 0, 0, 0,
                                      destination.glo, GL_TEXTURE_3D, 0, 0, 0, 0,
                                      width, height, depth)
