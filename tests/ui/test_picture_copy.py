"""The window's copy of a picture (explorer/ui/picture.py): texel for texel what the
pipeline left, the albedo's geometry edges as surface_edges() marks them, and a publish
that draws nothing (the edge pass runs when the albedo is first read)."""

from __future__ import annotations

import numpy as np
import pytest

from explorer.gl.call_counter import GlCallCounter
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings
from explorer.lpv.surface_edges import EDGE_FLAG, surface_edges
from explorer.ui.picture import Picture, SideDisplay, Stamp
from explorer.ui.view_composer import ViewComposer

SETTINGS = Settings(scene="cornell", grid_size=8, iterations=6, rsm_size=32, width=64,
                    height=40)
DISPLAY = SideDisplay(1.0, 1.0, "filmic", False)


def _array(texture) -> np.ndarray:
    """(H, W, 4) in the texture's own float type, row 0 at the bottom."""
    dtype = np.float16 if texture.dtype == "f2" else np.float32
    width, height = texture.size
    return np.frombuffer(texture.read(), dtype).reshape(height, width, 4)


@pytest.fixture()
def published(gl_context, programs):
    with Pipeline(SETTINGS, ctx=gl_context) as pipeline:
        result = pipeline.run(SETTINGS, need_audit=False)
        picture = Picture(gl_context, programs)
        with GlCallCounter() as counter:
            picture.copy_from(*pipeline.linear_textures, Stamp(1, True), result,
                              pipeline.fog_textures, pipeline.surface_textures)
        yield pipeline, picture, counter.tally
        picture.release()


def test_the_picture_holds_the_pipelines_texels_and_the_albedos_edges(published):
    pipeline, picture, _ = published
    direct, indirect, albedo = pipeline.linear_textures
    position, normal = (_array(t) for t in pipeline.surface_textures)
    for copy, source in ((picture.direct, direct), (picture.indirect, indirect)):
        assert copy.read() == source.read()
    want = _array(albedo).astype(np.float16)
    edges = surface_edges(position, normal)
    assert 0 < edges.sum() < (want[..., 3] > 0.5).sum()
    want[..., 3] = np.where(edges, np.float16(EDGE_FLAG), want[..., 3])
    got = _array(picture.albedo)
    assert got[..., 3].tobytes() == want[..., 3].tobytes()
    # GL leaves the rounding of a float written to a half float target open: one ulp
    np.testing.assert_allclose(got[..., :3], want[..., :3], rtol=2.0 ** -10, atol=0)


def test_publishing_draws_nothing_and_only_the_albedo_view_pays_the_edges(published,
                                                                         gl_context,
                                                                         programs):
    _, picture, tally = published
    assert tally.calls["draws"] == 0 and tally.calls["copies"] == 5, tally.calls
    composer = ViewComposer(gl_context, programs)
    try:
        with GlCallCounter() as counter:
            composer.side_image("A", picture, DISPLAY, "final")
        assert counter.tally.calls["draws"] == 1       # the view's pass alone
        with GlCallCounter() as counter:
            composer.side_image("A", picture, DISPLAY, "albedo")
            composer.difference(picture, picture, DISPLAY, DISPLAY, "albedo", 1.0)
        assert counter.tally.calls["draws"] == 3       # the edges once, then two views
    finally:
        composer.release()
