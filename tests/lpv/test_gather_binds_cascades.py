"""The gather binds its own cascades' grids at every draw: the uniforms it keeps from the
last draw point its samplers at units another pipeline (side B, the Error panel's) may
have bound its grids to since. Before, a side whose propagation changed but whose gather
uniforms did not gathered the other side's grids (found by the idle release's test,
issue #31)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings

BASE = Settings(scene="cornell", grid_size=8, iterations=4, rsm_size=32, width=40, height=32)


def test_two_pipelines_gather_their_own_cascades(ctx):
    for settings in (BASE.with_changes(cascades=2), BASE.with_changes(cascades=2, fog=True)):
        toggled = settings.with_changes(corrections=replace(
            settings.corrections, clamp_front_face=not settings.corrections.clamp_front_face))
        with Pipeline(settings, ctx=ctx) as a, Pipeline(settings, ctx=ctx) as b, \
                Pipeline(settings, ctx=ctx) as fresh:
            a.run(settings)
            b.run(settings)             # b's grids are bound last
            # a's propagation changes, its gather's uniforms do not
            shown = a.run(toggled)
            assert shown.stages_run[0] == "propagate"
            expected = fresh.run(toggled)
            assert np.array_equal(shown.indirect, expected.indirect, equal_nan=True)
            if settings.fog:
                assert np.array_equal(shown.fog.lpv, expected.fog.lpv,
                                      equal_nan=True)
