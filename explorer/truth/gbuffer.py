"""The G-buffer the reference gathers at: exactly the pixels of the Pipeline's frame.

A FrameResult that carries its G-buffer (``gbuffer_position``, ``gbuffer_normal``) is used
as it is. Otherwise the Pipeline's own G-buffer pass renders the scene again at the frame's
size: same shader, same camera, same two-sided normals (facing the viewer), same row order
(row 0 at the top), so the reference and the LPV see the same surface point per pixel.
"""

from __future__ import annotations

import numpy as np

from explorer.truth.reference import GBuffer


def scene_triangles(scene) -> np.ndarray:
    """(T, 3, 3) triangle soup of an ``explorer.scene.Scene``."""
    return np.asarray(scene.positions, np.float64).reshape(-1, 3, 3)


def scene_for(settings, loaded=None):
    """The scene a Settings renders, with its overrides applied (camera, lights, object
    transforms). ``loaded``: the scene ``settings.scene`` names as already loaded, before
    the overrides (``Pipeline.base_scene``, the window's ``runtime.scene_facts.scene``), which saves
    loading it again (the atrium takes a tenth of a second); None: loaded here."""
    from explorer.scene import load_scene

    if loaded is None:
        loaded = load_scene(settings.scene)
    return loaded.for_settings(settings)


def render_gbuffer(ctx, scene, width: int, height: int) -> GBuffer:
    """The Pipeline's G-buffer pass for ``scene`` at ``width × height``."""
    from explorer.gl.program import ProgramCache
    from explorer.lpv.passes.gbuffer import GBufferPass
    from explorer.lpv.passes.rsm import read_texture
    from explorer.scene.gpu import SceneBuffers

    programs = ProgramCache(ctx)
    buffers = SceneBuffers(ctx, scene)
    gbuffer_pass = GBufferPass(ctx, programs)
    try:
        gbuffer_pass.run(buffers, scene, (width, height))
        position, normal, albedo = (read_texture(t) for t in gbuffer_pass.textures)
    finally:
        gbuffer_pass.release()
        buffers.release()
        programs.release()
    return GBuffer(position[..., :3], normal[..., :3], albedo[..., :3], position[..., 3] > 0.5)


def gbuffer_from_frame(frame, scene=None, ctx=None) -> GBuffer:
    """The G-buffer of ``frame`` (a FrameResult): its own arrays when it has them,
    otherwise rendered again from ``scene`` (loaded from ``frame.settings`` when None)."""
    position = frame.gbuffer_position
    normal = frame.gbuffer_normal
    albedo = np.asarray(frame.albedo)[..., :3]
    if position is not None and normal is not None:
        position = np.asarray(position)
        if position.shape[-1] == 4:
            valid = position[..., 3] > 0.5
        else:  # no coverage channel: the clear colour leaves albedo at zero
            valid = np.any(albedo > 0, axis=-1)
        return GBuffer(position[..., :3], np.asarray(normal)[..., :3], albedo, valid)
    if scene is None:
        scene = scene_for(frame.settings)
    height, width = albedo.shape[:2]
    from explorer.gl.context import given_or_headless

    with given_or_headless(ctx) as ctx:
        return render_gbuffer(ctx, scene, width, height)
