"""What a stage keeps from one frame to the next while its frozen inputs are the same
objects (the frame's CPU side, issue #32 item 2): kept while they are, made anew when
they change."""

from __future__ import annotations

import numpy as np

from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings

SMALL = Settings(grid_size=8, iterations=4, rsm_size=32, width=32, height=32)


def test_the_rsm_views_are_kept_while_the_scene_is_the_same_and_follow_the_light(gl_context):
    pipeline = Pipeline(SMALL, gl_context)
    try:
        pipeline.run(SMALL, need_audit="off")
        stage = pipeline.stages["rsm"]
        views = stage.views(SMALL)
        pipeline.invalidate("rsm")
        pipeline.run(SMALL, need_audit="off")
        assert stage.views(SMALL) is views
        assert stage.views(SMALL.with_changes(rsm_size=16)) is not views
        moved = SMALL.with_changes(light=((0.2, 0.9, 0.1), (0.0, 0.0, 0.0)))
        moved_views = stage.views(moved)
        assert not np.array_equal(moved_views[0].view, views[0].view)
        result = pipeline.run(moved, need_audit="off")
        assert result.light_views[0] is moved_views[0]
    finally:
        pipeline.release()


def test_a_cascaded_frame_gathers_the_same_after_a_single_grid_frame(gl_context):
    """The gather keeps its uniforms for the same cascades; their textures are bound again
    each run (the units hold others between: here the single grid's propagation's), so a
    cascaded frame after another gathers what it gathered the first time, bit for bit."""
    cascaded = Settings(scene="room", grid_size=16, cascades=3, iterations=4, rsm_size=32,
                        width=32, height=32)
    pipeline = Pipeline(cascaded, gl_context)
    try:
        first = pipeline.run(cascaded, need_audit="off")
        pipeline.run(cascaded.with_changes(cascades=1), need_audit="off")
        again = pipeline.run(cascaded, need_audit="off")
        assert "gather" in again.stages_run
        assert np.array_equal(again.indirect, first.indirect)
        assert np.abs(first.indirect).max() > 0
    finally:
        pipeline.release()
