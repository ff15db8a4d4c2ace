"""The reference's G-buffer is the frame's: same pixels, same rows."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.truth.gbuffer import gbuffer_from_frame

TINY = Settings(scene="cornell", width=20, height=16, rsm_size=8, grid_size=8, iterations=1)


@pytest.fixture(scope="module")
def tiny_frame(gl_context):
    with Pipeline(TINY, gl_context) as pipeline:
        yield pipeline.run()


def test_gbuffer_matches_the_frame_pixel_for_pixel(ctx, tiny_frame):
    gbuffer = gbuffer_from_frame(tiny_frame, ctx=ctx)
    assert gbuffer.size == (20, 16)
    np.testing.assert_array_equal(gbuffer.albedo, tiny_frame.albedo)
    assert gbuffer.valid.mean() > 0.5  # the box fills most of the view
    inside = gbuffer.position[gbuffer.valid]
    assert np.all(np.abs(inside) <= 1.0 + 1e-4)
    np.testing.assert_allclose(np.linalg.norm(gbuffer.normal[gbuffer.valid], axis=-1), 1.0,
                               atol=1e-5)
    # the floor is at the bottom of the picture (row 0 is the top), facing up
    bottom = np.flatnonzero(gbuffer.valid[:, 10])[-1]
    assert gbuffer.position[bottom, 10, 1] < -0.9 and gbuffer.normal[bottom, 10, 1] > 0.99


def test_a_frame_that_carries_its_gbuffer_is_used_as_it_is(ctx):
    position = np.zeros((2, 3, 4))
    position[0, :, 3] = 1.0
    position[0, :, 0] = [0.1, 0.2, 0.3]
    normal = np.tile([0.0, 1.0, 0.0], (2, 3, 1))
    frame = SimpleNamespace(albedo=np.full((2, 3, 3), 0.5), gbuffer_position=position,
                            gbuffer_normal=normal)
    gbuffer = gbuffer_from_frame(frame)
    assert gbuffer.valid.tolist() == [[True] * 3, [False] * 3]
    np.testing.assert_array_equal(gbuffer.position[0, :, 0], [0.1, 0.2, 0.3])


def test_reference_for_a_frame_matches_the_numpy_sum(ctx, tiny_frame):
    """End to end on a Pipeline frame: its G-buffer, its VPLs, the scene's triangles."""
    from explorer.truth.gbuffer import scene_for, scene_triangles
    from explorer.truth.reference import numpy_reference_irradiance, outgoing_radiance
    from explorer.truth.render import lit_vpls, reference_for_frame

    radiance, gbuffer = reference_for_frame(tiny_frame, visibility=True, ctx=ctx)
    assert radiance.shape == tiny_frame.indirect.shape and radiance.max() > 0
    vpls = lit_vpls(tiny_frame.vpls)
    assert 0 < vpls.count <= tiny_frame.vpls.count
    expected = outgoing_radiance(gbuffer, numpy_reference_irradiance(
        gbuffer, vpls, 0.5 * tiny_frame.grid_spec.cell_size,
        scene_triangles(scene_for(tiny_frame.settings)), visibility=True))
    np.testing.assert_allclose(radiance, expected, rtol=1e-3, atol=1e-4 * expected.max())
