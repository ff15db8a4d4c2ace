"""The one-bounce reference renderer: GPU sum vs the numpy twin, visibility, linearity,
reciprocity, tiling and cancellation (tiny sizes for llvmpipe)."""

from __future__ import annotations

import numpy as np
import pytest

from explorer.lpv.vpl import VplArrays
from explorer.truth import Cancelled, GBuffer, build_bvh, reference_irradiance
from explorer.truth.reference import (
    ReferencePass,
    numpy_reference_irradiance,
    outgoing_radiance,
    segments_blocked,
)

MIN_DISTANCE = 0.05


def floor_gbuffer(width: int = 10, height: int = 8) -> GBuffer:
    """A floor (y = 0, normal +y) sampled on a 0.1 grid, one pixel left empty."""
    ys, xs = np.mgrid[0:height, 0:width]
    position = np.stack([xs * 0.1, np.zeros_like(xs, float), ys * 0.1], axis=-1)
    normal = np.broadcast_to([0.0, 1.0, 0.0], position.shape).copy()
    albedo = np.broadcast_to([0.8, 0.5, 0.2], position.shape).copy()
    valid = np.ones((height, width), bool)
    valid[0, 0] = False
    return GBuffer(position, normal, albedo, valid)


def ceiling_vpls(count: int = 6, seed: int = 3) -> VplArrays:
    """VPLs above the floor, facing mostly down."""
    rng = np.random.default_rng(seed)
    positions = np.c_[rng.uniform(0, 1, count), rng.uniform(0.2, 0.8, count),
                      rng.uniform(0, 0.8, count)]
    normals = rng.normal(size=(count, 3))
    normals[:, 1] = -np.abs(normals[:, 1]) - 0.5
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    flux = rng.uniform(0.1, 1.0, (count, 3))
    return VplArrays(positions, normals, flux, np.ones(count), 0.01)


BLOCKERS = np.array([
    [[0.2, 0.1, 0.1], [0.8, 0.1, 0.1], [0.5, 0.1, 0.8]],   # partly between VPLs and floor
    [[0.0, 0.9, 0.0], [1.0, 0.9, 0.0], [0.0, 0.9, 1.0]],   # above every VPL: never in the way
])


def test_gpu_sum_matches_numpy_without_visibility(ctx):
    gbuffer, vpls = floor_gbuffer(), ceiling_vpls()
    # tile_size/vpl_chunk smaller than the inputs so several dispatches accumulate.
    gpu = reference_irradiance(gbuffer, vpls, MIN_DISTANCE, ctx=ctx, tile_size=8, vpl_chunk=4)
    expected = numpy_reference_irradiance(gbuffer, vpls, MIN_DISTANCE)
    assert expected.max() > 0
    np.testing.assert_allclose(gpu, expected, rtol=1e-4, atol=1e-4 * expected.max())
    assert np.all(gpu[0, 0] == 0)  # no surface, no light


def test_gpu_sum_matches_numpy_with_visibility(ctx):
    gbuffer, vpls = floor_gbuffer(), ceiling_vpls()
    gpu = reference_irradiance(gbuffer, vpls, MIN_DISTANCE, BLOCKERS, True, ctx=ctx,
                               tile_size=8, vpl_chunk=4)
    expected = numpy_reference_irradiance(gbuffer, vpls, MIN_DISTANCE, BLOCKERS, True)
    unoccluded = numpy_reference_irradiance(gbuffer, vpls, MIN_DISTANCE)
    assert expected.sum() < 0.95 * unoccluded.sum()  # the blocker really casts a shadow
    np.testing.assert_allclose(gpu, expected, rtol=1e-4, atol=1e-4 * expected.max())


def test_one_vpl_closed_form_and_distance_clamp():
    """A VPL facing straight down at height h over a receiver facing up: E = Φ/(π h²),
    and the clamp replaces h² by r_min² when h < r_min."""
    gbuffer = GBuffer(np.zeros((1, 1, 3)), np.array([[[0.0, 1.0, 0.0]]]),
                      np.full((1, 1, 3), 0.5), np.ones((1, 1), bool))
    for height, expected_r2 in ((0.5, 0.25), (0.01, MIN_DISTANCE ** 2)):
        vpls = VplArrays(np.array([[0.0, height, 0.0]]), np.array([[0.0, -1.0, 0.0]]),
                         np.array([[1.0, 2.0, 3.0]]), np.ones(1), 0.01)
        irradiance = numpy_reference_irradiance(gbuffer, vpls, MIN_DISTANCE)
        np.testing.assert_allclose(irradiance[0, 0], np.array([1, 2, 3]) / (np.pi * expected_r2))
        radiance = outgoing_radiance(gbuffer, irradiance)
        np.testing.assert_allclose(radiance[0, 0], 0.5 / np.pi * irradiance[0, 0], rtol=1e-6)


def test_blocker_between_vpl_and_receiver_removes_the_light(ctx):
    gbuffer = GBuffer(np.zeros((1, 2, 3)), np.tile([0.0, 1.0, 0.0], (1, 2, 1)),
                      np.ones((1, 2, 3)), np.ones((1, 2), bool))
    gbuffer.position[0, 1] = (5.0, 0.0, 0.0)  # a second pixel far from the blocker
    vpls = VplArrays(np.array([[0.0, 1.0, 0.0]]), np.array([[0.0, -1.0, 0.0]]),
                     np.ones((1, 3)), np.ones(1), 0.01)
    blocker = np.array([[[-0.5, 0.5, -0.5], [0.5, 0.5, -0.5], [0.0, 0.5, 0.7]]])
    open_sky = reference_irradiance(gbuffer, vpls, MIN_DISTANCE, ctx=ctx)
    shadowed = reference_irradiance(gbuffer, vpls, MIN_DISTANCE, blocker, True, ctx=ctx)
    assert open_sky[0, 0, 0] > 0 and shadowed[0, 0, 0] == 0.0
    np.testing.assert_allclose(shadowed[0, 1], open_sky[0, 1], rtol=1e-6)


def test_linear_in_flux_and_additive_over_vpls(ctx):
    gbuffer, vpls = floor_gbuffer(6, 5), ceiling_vpls(4)
    base = reference_irradiance(gbuffer, vpls, MIN_DISTANCE, ctx=ctx)
    scaled = VplArrays(vpls.positions, vpls.normals, 2.5 * vpls.flux, vpls.depth, 0.01)
    np.testing.assert_allclose(reference_irradiance(gbuffer, scaled, MIN_DISTANCE, ctx=ctx),
                               2.5 * base, rtol=1e-5)
    halves = [VplArrays(vpls.positions[s], vpls.normals[s], vpls.flux[s], vpls.depth[s], 0.01)
              for s in (slice(0, 2), slice(2, 4))]
    parts = sum(reference_irradiance(gbuffer, h, MIN_DISTANCE, ctx=ctx) for h in halves)
    np.testing.assert_allclose(parts, base, rtol=1e-5, atol=1e-7)


def test_reciprocity_of_the_transport_kernel(ctx):
    """Swapping sender and receiver (positions and normals) keeps E/Φ: the kernel
    cosθ_j·cosθ_p/(π r²) is symmetric."""
    a, n_a = np.array([0.1, 0.0, 0.2]), np.array([0.0, 1.0, 0.0])
    b, n_b = np.array([0.4, 0.6, 0.5]), np.array([-0.3, -0.9, 0.1]) / np.sqrt(0.91)

    def transfer(src, n_src, dst, n_dst):
        gbuffer = GBuffer(dst[None, None], n_dst[None, None], np.ones((1, 1, 3)),
                          np.ones((1, 1), bool))
        vpls = VplArrays(src[None], n_src[None], np.ones((1, 3)), np.ones(1), 0.01)
        return reference_irradiance(gbuffer, vpls, MIN_DISTANCE, ctx=ctx)[0, 0, 0]

    forward, backward = transfer(a, n_a, b, n_b), transfer(b, n_b, a, n_a)
    assert forward > 0
    assert forward == pytest.approx(backward, rel=1e-5)


def test_bvh_traversal_agrees_with_brute_force(ctx):
    """Many small triangles (a deep BVH): the GPU's any-hit walk and the numpy brute force
    agree ray for ray."""
    rng = np.random.default_rng(7)
    centres = rng.uniform([0, 0.1, 0], [1, 0.5, 0.8], (200, 3))
    triangles = centres[:, None, :] + rng.normal(scale=0.04, size=(200, 3, 3))
    bvh = build_bvh(triangles, leaf_size=2)
    assert bvh.depth >= 6 and bvh.triangle_count == 200
    gbuffer, vpls = floor_gbuffer(8, 6), ceiling_vpls(5)
    gpu = reference_irradiance(gbuffer, vpls, MIN_DISTANCE, bvh, True, ctx=ctx)
    expected = numpy_reference_irradiance(gbuffer, vpls, MIN_DISTANCE, triangles, True)
    np.testing.assert_allclose(gpu, expected, rtol=1e-4, atol=1e-4 * expected.max())


def test_segments_blocked_brute_force():
    triangle = np.array([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]])
    starts = np.array([[0.2, 1.0, 0.2], [0.2, 1.0, 0.2], [2.0, 1.0, 2.0]])
    ends = np.array([[0.2, -1.0, 0.2], [0.2, 0.5, 0.2], [2.0, -1.0, 2.0]])
    assert segments_blocked(starts, ends, triangle).tolist() == [True, False, False]


def test_progress_reports_every_dispatch_and_cancel_raises(ctx):
    gbuffer, vpls = floor_gbuffer(), ceiling_vpls()
    seen: list[float] = []
    reference = ReferencePass(ctx)
    try:
        reference.run(gbuffer, vpls, MIN_DISTANCE, tile_size=8, vpl_chunk=3,
                      progress=lambda done: seen.append(done))
        assert seen[-1] == pytest.approx(1.0) and seen == sorted(seen)
        assert len(seen) == 2 * 2  # 2 tiles of 8×8 over 10×8 pixels, 2 chunks of 3 VPLs
        calls: list[float] = []
        with pytest.raises(Cancelled, match="cancelled after 1 of 4"):
            reference.run(gbuffer, vpls, MIN_DISTANCE, tile_size=8, vpl_chunk=3,
                          progress=lambda done: calls.append(done) or False)
        assert len(calls) == 1
    finally:
        reference.release()


def test_bad_input_is_named(ctx):
    gbuffer, vpls = floor_gbuffer(), ceiling_vpls()
    with pytest.raises(ValueError, match="triangles"):
        reference_irradiance(gbuffer, vpls, MIN_DISTANCE, None, True, ctx=ctx)
    with pytest.raises(ValueError, match="min_distance"):
        reference_irradiance(gbuffer, vpls, -1.0, ctx=ctx)
    with pytest.raises(ValueError, match="normal must have shape"):
        GBuffer(gbuffer.position, gbuffer.normal[:, :3], gbuffer.albedo, gbuffer.valid)
    with pytest.raises(ValueError, match=r"\(T, 3, 3\)"):
        build_bvh(np.zeros((4, 3)))


def test_vpl_textures_skip_invalid_texels(ctx):
    """A 3×2 VPL texture set (as the RSM hands it over) with one texel that saw nothing:
    the GPU sums only the valid texels, row by row."""
    import moderngl

    from explorer.lpv.vpl import VplTextures

    vpls = ceiling_vpls(6)
    position = np.hstack([vpls.positions, np.ones((6, 1))]).astype(np.float32)
    position[4, 3] = 0.0  # the light saw no surface here
    normal = np.hstack([vpls.normals, np.ones((6, 1))]).astype(np.float32)
    flux = np.hstack([vpls.flux, np.zeros((6, 1))]).astype(np.float32)
    textures = []
    for data in (position, normal, flux):
        texture = ctx.texture((3, 2), 4, data.tobytes(), dtype="f4")
        texture.filter = (moderngl.NEAREST, moderngl.NEAREST)
        textures.append(texture)
    handed_over = VplTextures(*textures, texel_area=0.01)
    try:
        gbuffer = floor_gbuffer(6, 5)
        gpu = reference_irradiance(gbuffer, handed_over, MIN_DISTANCE, ctx=ctx, vpl_chunk=4)
    finally:
        handed_over.release()
    keep = np.arange(6) != 4
    valid_only = VplArrays(vpls.positions[keep], vpls.normals[keep], vpls.flux[keep],
                           vpls.depth[keep], 0.01)
    expected = numpy_reference_irradiance(gbuffer, valid_only, MIN_DISTANCE)
    np.testing.assert_allclose(gpu, expected, rtol=1e-4, atol=1e-4 * expected.max())


def closed_box(half: float = 1.0) -> np.ndarray:
    """The 12 triangles of a cube centred on the origin (a convex enclosure)."""
    corners = np.array([[x, y, z] for x in (-half, half) for y in (-half, half)
                        for z in (-half, half)])
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4),
             (1, 5, 7, 3)]
    return np.array([[corners[a], corners[b], corners[c]] for a, b, c, d in faces] +
                    [[corners[a], corners[c], corners[d]] for a, b, c, d in faces])


def many_vpls_inside(count: int = 3000) -> VplArrays:
    rng = np.random.default_rng(11)
    normals = rng.normal(size=(count, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    return VplArrays(rng.uniform(-0.9, 0.9, (count, 3)), normals,
                     rng.uniform(0.0, 1.0, (count, 3)), np.ones(count), 0.01)


def test_inside_a_convex_box_visibility_changes_nothing(ctx):
    """Every VPL and pixel lies inside a closed cube, so no shadow ray can be blocked:
    the visible sum equals the unoccluded one. Many VPLs per dispatch make this the test
    that catches a driver cutting the shader's loops short (llvmpipe's loop limit)."""
    gbuffer = floor_gbuffer(4, 3)
    gbuffer.position[..., 1] = -0.5  # a floor inside the box
    vpls = many_vpls_inside()
    open_sky = reference_irradiance(gbuffer, vpls, MIN_DISTANCE, ctx=ctx)
    boxed = reference_irradiance(gbuffer, vpls, MIN_DISTANCE, closed_box(), True, ctx=ctx)
    assert open_sky.max() > 0
    np.testing.assert_allclose(boxed, open_sky, rtol=1e-5)


def test_a_chunk_cut_short_by_the_driver_is_refused(ctx, monkeypatch):
    """With the chunk budget lifted, llvmpipe ends the loop early; the pass must raise
    instead of returning too little light (on a GPU without the limit it just matches)."""
    from explorer.truth import reference as reference_module

    gbuffer = floor_gbuffer(2, 1)
    gbuffer.position[..., 1] = -0.5
    vpls = many_vpls_inside(6000)
    expected = reference_irradiance(gbuffer, vpls, MIN_DISTANCE, ctx=ctx)
    monkeypatch.setattr(reference_module, "LOOP_BUDGET", 10 ** 9)
    try:
        lifted = reference_irradiance(gbuffer, vpls, MIN_DISTANCE, closed_box(), True,
                                      ctx=ctx, vpl_chunk=6000)
    except reference_module.IncompleteRender as exc:
        assert "loop" in str(exc)
    else:
        renderer = str(ctx.info.get("GL_RENDERER", "")).lower()
        assert "llvmpipe" not in renderer, "llvmpipe cut nothing: the limit test is stale"
        np.testing.assert_allclose(lifted, expected, rtol=1e-5)


def test_the_bvh_built_node_by_node_is_the_one_shot_bvh():
    """BvhBuilder (the window builds a large scene's BVH between frames): a node per step,
    the same nodes and triangle order as build_bvh, and advance with no time does one."""
    from explorer.truth.bvh import BvhBuilder

    triangles = np.random.default_rng(5).random((300, 3, 3))
    whole = build_bvh(triangles, leaf_size=2)
    builder = BvhBuilder(triangles, leaf_size=2)
    steps = 0
    while not builder.done:
        assert builder.advance(0.0) == 1
        steps += 1
        assert 0.0 <= builder.fraction <= 1.0
    assert builder.step(5) == 0 and builder.fraction == 1.0
    assert steps == len(whole.nodes)
    stepped = builder.result()
    assert stepped.depth == whole.depth
    np.testing.assert_array_equal(stepped.triangles, whole.triangles)
    assert stepped.nodes.tobytes() == whole.nodes.tobytes()
    with pytest.raises(RuntimeError, match="not finished"):
        BvhBuilder(triangles).result()
