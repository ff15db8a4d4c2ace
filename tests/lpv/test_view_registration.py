"""Every camera view buffer (final, direct, indirect, albedo) is drawn from one camera,
projection and size: their surfaces match an independent triangle-id raster pixel for
pixel, each block's silhouette is outlined in the albedo view, and the window's albedo
copy marks the same edge pixels as the headless view."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from explorer.lpv.passes.rsm import read_texture
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.lpv.surface_edges import EDGE_FLAG, EDGE_SHADE, surface_edges
from explorer.truth.gbuffer import scene_for
from explorer.truth.surface_masks import render_triangle_ids, surface_masks

TEXTURED = str(Path(__file__).resolve().parents[2] / "examples/textured-room/scene.toml")
CAMERA_VIEWS = ("final", "direct", "indirect", "albedo")
SCENES = {"cornell": ("tall block", "short block"), TEXTURED: ("block",)}
"""Each scene and the objects standing before its walls."""


def _settings(scene: str) -> Settings:
    # a wide image, so that a transposed or square-stretched buffer cannot pass
    return Settings(scene=scene, grid_size=16, iterations=4, rsm_size=64, width=96,
                    height=64)


@pytest.fixture(scope="module", params=list(SCENES), ids=["cornell", "textured-room"])
def frame(request, gl_context):
    settings = _settings(request.param)
    with Pipeline(settings, ctx=gl_context) as pipeline:
        result = pipeline.run(settings)
        views = {name: pipeline.view(name) for name in CAMERA_VIEWS}
        targets = pipeline.state.gather_pass.targets
        gathered = {name: read_texture(targets[name]) for name in ("direct", "indirect")}
        scene = scene_for(settings)
        ids = render_triangle_ids(gl_context, scene, settings.width, settings.height)
        yield request.param, pipeline, result, views, gathered, scene, ids


def test_every_camera_buffer_covers_the_triangle_raster_pixel_for_pixel(frame):
    scene_name, _, result, views, gathered, _, ids = frame
    seen = ids >= 0
    assert seen.any()
    # the Cornell box is seen from outside, its outline against the background; the
    # textured room from inside (its blocks' silhouettes are the next test's)
    assert seen.all() == (scene_name == TEXTURED)
    np.testing.assert_array_equal(result.gbuffer_position[..., 3] > 0.5, seen)
    for name, target in gathered.items():
        np.testing.assert_array_equal(target[..., 3] > 0.5, seen, err_msg=name)
    for name, image in views.items():
        assert image.shape == (*seen.shape, 3), name
        assert not image[~seen].any(), f"{name} draws off the surfaces"
    np.testing.assert_array_equal(views["albedo"].max(axis=-1) > 0, seen)


def test_each_block_silhouette_is_outlined_in_the_albedo_view(frame):
    scene_name, _, result, views, _, scene, ids = frame
    edges = surface_edges(result.gbuffer_position, result.gbuffer_normal)
    for name, block in surface_masks(scene, ids, SCENES[scene_name]).items():
        inside = block[1:-1, 1:-1]
        around = (block[:-2, 1:-1] & block[2:, 1:-1] & block[1:-1, :-2] & block[1:-1, 2:])
        silhouette = np.zeros_like(block)
        silhouette[1:-1, 1:-1] = inside & ~around
        assert silhouette.sum() > 10, name
        # the block's border, on the block or on the pixel beside it, is an edge pixel
        near = edges | np.roll(edges, 1, 0) | np.roll(edges, -1, 0) | \
            np.roll(edges, 1, 1) | np.roll(edges, -1, 1)
        assert near[silhouette].mean() > 0.95, name
    # the edge pixels are the albedo darkened, the others the albedo itself
    from explorer.lpv.twin.tonemap import linear_to_srgb

    want = linear_to_srgb(np.where(edges[..., None], EDGE_SHADE * result.albedo, result.albedo))
    np.testing.assert_allclose(views["albedo"], want, atol=1e-6)


def test_the_window_copy_marks_the_same_edges_as_the_headless_view(frame, gl_context):
    from explorer.gl.program import ProgramCache
    from explorer.ui.picture import Picture, Stamp

    _, pipeline, result, _, _, _, _ = frame
    programs = ProgramCache(gl_context)
    picture = Picture(gl_context, programs)
    try:
        picture.copy_from(*pipeline.linear_textures, Stamp(1, True), result,
                          surfaces=pipeline.surface_textures)
        albedo = np.frombuffer(picture.albedo.read(), np.float16).reshape(
            result.albedo.shape[0], result.albedo.shape[1], 4)[::-1].astype(np.float32)
    finally:
        picture.release()
        programs.release()
    edges = surface_edges(result.gbuffer_position, result.gbuffer_normal)
    assert edges.any()
    np.testing.assert_array_equal(albedo[..., 3] == np.float16(EDGE_FLAG), edges)
    np.testing.assert_array_equal(albedo[..., 3] > 0.5, result.gbuffer_position[..., 3] > 0.5)


def test_the_textured_floor_is_lit_through_the_same_texels(frame):
    """direct = albedo·E/π (docs/MODEL.md "Final gather"): on the checker floor the ratio
    direct/albedo is the irradiance, smooth across the checker's edges, only if both
    buffers sample the texture at the same pixels."""
    scene_name, _, result, _, _, scene, ids = frame
    if scene_name != TEXTURED:
        pytest.skip("the Cornell box has no texture")
    floor = surface_masks(scene, ids, ("floor",))["floor"]
    albedo = result.albedo[..., 1].astype(np.float64)
    direct = result.direct[..., 1].astype(np.float64)
    lit = floor & (direct > 1e-4 * direct.max()) & (albedo > 0.02)
    ratio = np.where(lit, direct / np.where(lit, albedo, 1.0), 1.0)
    pairs = lit[:, 1:] & lit[:, :-1]     # horizontal neighbours both lit floor
    albedo_step = np.abs(np.log(albedo[:, 1:][pairs] / albedo[:, :-1][pairs]))
    ratio_step = np.abs(np.log(ratio[:, 1:][pairs] / ratio[:, :-1][pairs]))
    checker = albedo_step > 0.5              # the texture's dark-to-light edges
    assert checker.sum() > 10
    # (an albedo one pixel off puts the checker's own step, about 1.2, into the ratio)
    assert np.median(ratio_step[checker]) < 0.05 * np.median(albedo_step[checker])
