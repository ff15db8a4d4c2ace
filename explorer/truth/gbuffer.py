"""The G-buffer the reference gathers at: from a FrameResult, or rasterised from the scene.

When the Pipeline's FrameResult carries its G-buffer (``gbuffer_position`` and
``gbuffer_normal``), the reference uses exactly those pixels. Otherwise this module
rasterises the scene with the scene's camera (``shaders/reference_gbuffer.glsl``) and
orients the rows like the frame's ``albedo`` image, so both images cover the same pixels.
"""

from __future__ import annotations

import numpy as np

from explorer.truth.reference import GBuffer


def scene_triangles(scene) -> np.ndarray:
    """(T, 3, 3) triangle soup of a ``explorer.scene.Scene``."""
    return np.asarray(scene.positions, np.float64).reshape(-1, 3, 3)


def rasterize_gbuffer(ctx, scene, width: int, height: int) -> GBuffer:
    """World position, normal and albedo per pixel seen through ``scene.camera``; rows in
    the order GL reads them back (row 0 = bottom of the picture)."""
    import moderngl

    from explorer.gl.program import preprocess
    from explorer.resources import shader_dir

    view = scene.camera.view_matrix()
    projection = scene.camera.projection_matrix(width / height, scene.bounds_min,
                                                scene.bounds_max)
    # Compiled here rather than through load_program, whose render-program path passes
    # varyings=None, which moderngl 5.12 rejects (reported to the coordinator).
    path = shader_dir() / "reference_gbuffer.glsl"
    program = ctx.program(vertex_shader=preprocess(path, "VERTEX_SHADER"),
                          fragment_shader=preprocess(path, "FRAGMENT_SHADER"))
    owned = [program]
    # Rebind what was bound before releasing our framebuffer: moderngl re-binds the
    # "current" framebuffer when it creates the next one, and a released one is an error.
    restore = ctx.fbo if ctx.fbo is not None else ctx.detect_framebuffer(0)
    try:
        # numpy matrices act on column vectors; a GLSL mat4 is filled column by column.
        program["u_view_projection"].value = tuple(
            float(v) for v in (np.asarray(projection) @ np.asarray(view)).T.ravel())
        vbo = ctx.buffer(scene.vertex_bytes())
        owned.append(vbo)
        vao = ctx.vertex_array(program, [(vbo, "3f 3f 3f", "in_position", "in_normal",
                                          "in_albedo")])
        owned.append(vao)
        targets = [ctx.texture((width, height), 4, dtype="f4") for _ in range(3)]
        depth = ctx.depth_renderbuffer((width, height))
        owned.extend(targets + [depth])
        fbo = ctx.framebuffer(targets, depth)
        owned.append(fbo)
        fbo.use()
        fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        ctx.enable(moderngl.DEPTH_TEST)
        vao.render(moderngl.TRIANGLES)
        ctx.disable(moderngl.DEPTH_TEST)
        position, normal, albedo = (
            np.frombuffer(fbo.read(attachment=i, components=4, dtype="f4"), np.float32)
            .reshape(height, width, 4) for i in range(3))
    finally:
        restore.use()
        for obj in reversed(owned):
            obj.release()
    valid = position[..., 3] > 0.5
    return GBuffer(position[..., :3].copy(), normal[..., :3].copy(), albedo[..., :3].copy(),
                   valid)


def flipped(gbuffer: GBuffer) -> GBuffer:
    """The same G-buffer with its rows in the opposite order."""
    return GBuffer(gbuffer.position[::-1].copy(), gbuffer.normal[::-1].copy(),
                   gbuffer.albedo[::-1].copy(), gbuffer.valid[::-1].copy())


def oriented_like(gbuffer: GBuffer, albedo: np.ndarray) -> GBuffer:
    """``gbuffer`` or its row flip, whichever matches a reference albedo image better."""
    albedo = np.asarray(albedo, np.float64)
    if albedo.shape != gbuffer.albedo.shape:
        raise ValueError(f"albedo image has shape {albedo.shape}, the G-buffer "
                         f"{gbuffer.albedo.shape}")
    other = flipped(gbuffer)
    keep = np.abs(gbuffer.albedo - albedo).mean()
    flip = np.abs(other.albedo - albedo).mean()
    return other if flip < keep else gbuffer


def gbuffer_from_frame(frame, scene=None, ctx=None) -> GBuffer:
    """The G-buffer of ``frame`` (a FrameResult): its own arrays when it has them,
    otherwise rasterised from ``scene`` (loaded from ``frame.settings`` when None)."""
    position = getattr(frame, "gbuffer_position", None)
    normal = getattr(frame, "gbuffer_normal", None)
    if position is not None and normal is not None:
        position = np.asarray(position)
        valid = position[..., 3] > 0.5 if position.shape[-1] == 4 else np.any(
            np.asarray(frame.albedo) > 0, axis=-1)
        return GBuffer(position[..., :3], np.asarray(normal)[..., :3],
                       np.asarray(frame.albedo)[..., :3], valid)
    if scene is None:
        scene = scene_for(frame.settings)
    height, width = np.asarray(frame.albedo).shape[:2]
    own_ctx = ctx is None
    if own_ctx:
        from explorer.gl.context import create_headless_context

        ctx = create_headless_context()
    try:
        gbuffer = rasterize_gbuffer(ctx, scene, width, height)
    finally:
        if own_ctx:
            ctx.release()
    return oriented_like(gbuffer, frame.albedo)


def scene_for(settings):
    """The scene a Settings renders, with its camera/light overrides applied."""
    from explorer.scene import load_scene

    return load_scene(settings.scene).with_overrides(settings.camera, settings.light,
                                                     settings.light_flux)
