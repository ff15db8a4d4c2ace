"""A light view that is gone takes its GPU memory with it (issue #31 item 6): after a
point light (six RSM views, downsampled, their atlases and read-backs) the spot alone,
not downsampled, keeps one RSM pass, no downsample pass, no atlas and one view's
read-backs, and its frame is the frame
of a pipeline that never saw the point light, bit for bit."""

from __future__ import annotations

import numpy as np

from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings

CORNELL = Settings(scene="cornell", grid_size=8, iterations=4, rsm_size=32, width=48,
                   height=40)


def test_views_gone_are_released(ctx):
    spot, both = CORNELL.with_changes(lights=("spot",)), CORNELL.with_changes(
        lights=("spot", "bulb"), downsample="average")
    with Pipeline(spot, ctx=ctx) as seen, Pipeline(spot, ctx=ctx) as fresh:
        assert len(seen.run(both).vpl_sets) == 7
        views = seen.light_views
        assert len(views.rsm.passes) == 7 and views._rsm_atlas.layout is not None
        shown = seen.run(spot)
        assert len(views.rsm.passes) == 1 and len(views.downsample.passes) == 0
        assert views._rsm_atlas.layout is None and views._vpl_atlas.layout is None
        assert len(seen.stages["downsample"].reads) == 1
        assert len(seen.stages["rsm"].reads) == 3           # position, normal, flux
        expected = fresh.run(spot)
        for name in ("direct", "indirect", "rsm_flux"):
            assert np.array_equal(getattr(shown, name), getattr(expected, name),
                                  equal_nan=True), name
        assert np.array_equal(shown.accumulated, expected.accumulated, equal_nan=True)
