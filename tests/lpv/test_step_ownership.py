"""The propagation steps (grid_0..grid_N) live only in the frames that asked for them:
the pipeline hands its frame the list it recorded (no copy) and keeps none past a job
that did not ask for them."""

from __future__ import annotations

import gc
import weakref

from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings

SMALL = Settings(scene="cornell", grid_size=8, iterations=3, rsm_size=32, width=48,
                 height=36, cascades=2)


def test_a_frame_that_does_not_ask_for_the_steps_holds_none_and_frees_them(gl_context):
    with Pipeline(SMALL, ctx=gl_context) as pipeline:
        kept = pipeline.run(SMALL, keep_steps=True)
        assert all(level.steps is not None and len(level.steps) == 4
                   for level in kept.cascades)
        # the frame's steps are the ones the pipeline recorded, not a copy of them
        assert [level.output.steps for level in pipeline.state.cascades] == \
            [level.steps for level in kept.cascades]
        assert all(level.output.steps is frame_level.steps for level, frame_level
                   in zip(pipeline.state.cascades, kept.cascades))
        refs = [weakref.ref(level.steps[-1]) for level in kept.cascades]
        lean = pipeline.run(SMALL, keep_steps=False)      # nothing to propagate again
        assert "propagate" not in lean.stages_run
        assert all(level.steps is None for level in lean.cascades)
        del kept
        gc.collect()
        assert all(ref() is None for ref in refs), "the pipeline kept the steps"
        again = pipeline.run(SMALL, keep_steps=True)      # asked again: propagated again
        assert "propagate" in again.stages_run
        assert all(len(level.steps) == 4 for level in again.cascades)
