"""Pixel masks of a scene's named surfaces (explorer/scene/parts.py): which pixels of the
camera's view see the ``floor``, the ``tall block``, the atrium's ``north curtains``.

The triangle under each pixel comes from the GPU, not from matching positions: a pass
with the G-buffer's camera, projection and depth test (shaders/triangle_id.glsl) writes
the index of the triangle that wins each pixel, so a mask holds exactly the pixels whose
G-buffer surface is that part's. ``lpv-explorer compare --region-mask NAME`` reports the
metrics over these masks.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from explorer.scene.parts import surface_names

MAX_TRIANGLES = 2**24 - 1
"""Triangles whose index + 1 a float32 target holds exactly (shaders/triangle_id.glsl)."""


def check_surface_names(scene, names: Iterable[str]) -> tuple[str, ...]:
    """``names`` if each is a surface of ``scene``; ValueError (one line, the scene's
    surfaces listed) otherwise."""
    known = surface_names(scene).names
    names = tuple(names)
    for name in names:
        if name not in known:
            raise ValueError(f"scene {scene.name!r} has no surface named {name!r}; its "
                             f"surfaces are: {', '.join(known)}")
    return names


def render_triangle_ids(ctx, scene, width: int, height: int) -> np.ndarray:
    """(H, W) index of the triangle each pixel sees (−1: no surface), row 0 at the top
    like the G-buffer (explorer/truth/gbuffer.py ``render_gbuffer``)."""
    from explorer.gl.program import ProgramCache, set_uniforms
    from explorer.gl.targets import RenderTargets
    from explorer.lpv.passes.gbuffer import camera_uniforms
    from explorer.lpv.passes.rsm import read_texture
    from explorer.scene.gpu import SceneBuffers

    if scene.triangle_count > MAX_TRIANGLES:
        raise ValueError(f"scene {scene.name!r} has {scene.triangle_count} triangles; "
                         f"surface masks handle at most {MAX_TRIANGLES}")
    import moderngl

    programs = ProgramCache(ctx)
    buffers = SceneBuffers(ctx, scene)
    targets = RenderTargets(ctx, ("f4",), depth=True, enable=moderngl.DEPTH_TEST)
    try:
        targets.allocate((width, height))
        program = programs.get("triangle_id.glsl")
        set_uniforms(program, camera_uniforms(scene, (width, height)))   # the G-buffer's
        with targets.drawing(clear=True):
            buffers.draw(program)
        ids = read_texture(targets.textures[0])[..., 0]
    finally:
        targets.release()
        buffers.release()
        programs.release()
    return np.rint(ids).astype(np.int64) - 1


def surface_masks(scene, triangle_ids: np.ndarray, names: Iterable[str]) -> dict[str, np.ndarray]:
    """(H, W) bool mask per name: the pixels whose triangle (``triangle_ids``, from
    :func:`render_triangle_ids`) is a surface of that name."""
    surfaces = surface_names(scene)
    names = check_surface_names(scene, names)
    seen = triangle_ids >= 0
    pixel_names = np.full(triangle_ids.shape, -1, np.int64)
    pixel_names[seen] = surfaces.triangle_names[triangle_ids[seen]]
    return {name: pixel_names == surfaces.names.index(name) for name in names}
