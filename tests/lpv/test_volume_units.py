"""The injection and the geometry volume in units of one draw, one copy or one merge (issue
#32 item 3: a 64³ level's injection was one unit of 36 ms on llvmpipe, its geometry volume
one of 43–100 ms): each unit does at most one of them, the progress counts them, and the
grids built across units, with another pipeline's units run between them, are the one-shot
grids bit for bit."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings

BASE = Settings(scene="cornell", grid_size=8, iterations=4, rsm_size=32, width=40, height=32,
                geometry_volume="one-sided", bounces=2)
OPS = ("draw_points_additively", "copy_volume", "merge_volumes")
"""The GL work a unit of the two stages may do once."""


def record_ops(monkeypatch, ops: list[str]) -> None:
    """Append the name of each draw, copy and merge the two passes do to ``ops``."""
    inject = sys.modules["explorer.lpv.passes.inject"]
    geometry = sys.modules["explorer.lpv.passes.geometry"]
    for module in (inject, geometry):
        for name in OPS:
            original = getattr(module, name, None)
            if original is None:
                continue

            def counted(*args, _original=original, _name=name, **kwargs):
                ops.append(_name)
                return _original(*args, **kwargs)

            monkeypatch.setattr(module, name, counted)


def units_of(pipe: Pipeline, settings: Settings, other: Pipeline, other_settings: Settings,
             ops: list[str]):
    """Run ``settings`` one unit a call, a unit of ``other`` between every two: the result
    and, per unit of the inject and geometry stages, (stage, done, total, its GL work)."""
    units: list[tuple[str, int, int, list[str]]] = []

    def report(stage, done, total):
        if done:
            units.append((stage, done, total, list(ops)))
        ops.clear()

    job = pipe.start(settings, keep_steps=True, progress=report)
    between = other.start(other_settings, progress=lambda *call: ops.clear())
    while not job.done:
        job.advance(0.0)                 # one unit a call
        if not between.done:
            between.advance(0.0)
    return job.result, [unit for unit in units if unit[0] in ("inject", "geometry")]


@pytest.mark.parametrize("changes, views", [
    ({}, 1),
    ({"lights": ("spot", "lamp"), "camera_occluders": True}, 2),
])
def test_each_unit_of_a_volume_is_one_draw_copy_or_merge_and_the_grids_are_the_same(
        gl_context, ctx, monkeypatch, changes, views):
    settings = BASE.with_changes(**changes)
    other_settings = BASE.with_changes(grid_size=12, rsm_size=16, injection_offset_cells=0.5)
    with Pipeline(settings, ctx=gl_context) as pipe:
        whole = pipe.run(settings, keep_steps=True)
    ops: list[str] = []
    record_ops(monkeypatch, ops)
    with Pipeline(settings, ctx=gl_context) as pipe, \
            Pipeline(other_settings, ctx=gl_context) as other:
        split, units = units_of(pipe, settings, other, other_settings, ops)
    inject = [unit for unit in units if unit[0] == "inject"]
    geometry = [unit for unit in units if unit[0] == "geometry"]
    # the injection: the draw, then each channel's copy
    assert [unit[3] for unit in inject] == [["draw_points_additively"]] + [["copy_volume"]] * 3
    assert [unit[1:3] for unit in inject] == [(k, 4) for k in range(1, 5)]
    # the geometry volume: per view its draws and its two copies, each further view and the
    # camera's surfels (several views) merged in a unit of their own, then the read taken
    per_view = [["draw_points_additively"], ["copy_volume"], ["copy_volume"]]
    further = per_view + [["merge_volumes"]]
    expected = per_view + further * (views - 1 + (views > 1)) + [[]]
    assert [unit[3] for unit in geometry] == expected
    assert [unit[1:3] for unit in geometry] == [(k, len(expected))
                                                for k in range(1, len(expected) + 1)]
    # the same grids, bit for bit
    level, level_whole = split.cascades[0], whole.cascades[0]
    assert np.abs(level.steps[0]).max() > 0 and np.abs(level.geometry_volume).max() > 0
    assert np.array_equal(level.steps[0], level_whole.steps[0])            # the injected grid
    assert np.array_equal(level.geometry_volume, level_whole.geometry_volume)
    assert np.array_equal(level.accumulated, level_whole.accumulated)
    assert np.array_equal(split.indirect, whole.indirect)
