"""A large grid's injection, geometry volume and propagation start in units of one draw, one
copy or one merge (issue #32 item 3: at 64³ on llvmpipe the injection was one unit of
36 ms, the propagation's start one of 33 ms): each unit does at most one of them, the
progress counts them, and the grids built across units, with another pipeline's units run
between them, are the one-shot grids bit for bit. A small grid's stay one unit each."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings

BASE = Settings(scene="cornell", grid_size=8, iterations=4, rsm_size=32, width=40, height=32,
                geometry_volume="one-sided", bounces=2)
OPS = ("draw_points_additively", "copy_volume", "merge_volumes", "copy_volumes")
"""The GL work a unit of the three stages may do once (``copy_volumes``: several copies
in a row, recorded as that many ``copy_volume``)."""
STAGES = ("inject", "geometry", "propagate")
PASSES = tuple(f"explorer.lpv.passes.{name}" for name in STAGES)


def record_ops(monkeypatch, ops: list[str]) -> None:
    """Append the name of each draw, copy and merge the three passes do to ``ops``."""
    for module in map(sys.modules.__getitem__, PASSES):
        for name in OPS:
            original = getattr(module, name, None)
            if original is None:
                continue

            def counted(*args, _original=original, _name=name, **kwargs):
                if _name == "copy_volumes":
                    ops.extend(["copy_volume"] * len(args[1]))
                else:
                    ops.append(_name)
                return _original(*args, **kwargs)

            monkeypatch.setattr(module, name, counted)


def units_of(pipe: Pipeline, settings: Settings, other: Pipeline, other_settings: Settings,
             ops: list[str]):
    """Run ``settings`` one unit a call, a unit of ``other`` between every two: the result,
    per unit of the three stages (stage, its GL work) and their progress reports after a
    unit (stage, done, total)."""
    units: list[tuple[str, list[str]]] = []
    reports: list[tuple[str, int, int]] = []
    stage_work = pipe.stage_work

    def recorded(name, job):
        work = stage_work(name, job)
        while True:
            ops.clear()
            try:
                value = next(work)
            except StopIteration:
                units.append((name, list(ops)))
                return
            units.append((name, list(ops)))
            yield value

    pipe.stage_work = recorded
    job = pipe.start(settings, keep_steps=True,
                     progress=lambda *call: reports.append(call) if call[1] else None)
    between = other.start(other_settings)
    while not job.done:
        job.advance(0.0)                 # one unit a call
        if not between.done:
            between.advance(0.0)
    return (job.result, [unit for unit in units if unit[0] in STAGES],
            [call for call in reports if call[0] in STAGES])


@pytest.mark.parametrize("changes, views", [
    ({}, 1),
    ({"lights": ("spot", "lamp"), "camera_occluders": True}, 2),
])
def test_each_unit_of_a_large_volume_is_one_draw_copy_or_merge_and_the_grids_are_the_same(
        gl_context, ctx, monkeypatch, changes, views):
    settings = BASE.with_changes(**changes)
    other_settings = BASE.with_changes(grid_size=12, rsm_size=16, injection_offset_cells=0.5)
    with Pipeline(settings, ctx=gl_context) as pipe:
        whole = pipe.run(settings, keep_steps=True)
    # every volume copied apart, as a 64³ grid's are
    monkeypatch.setattr(sys.modules["explorer.lpv.passes.textures"], "APART_TEXELS", 0)
    ops: list[str] = []
    record_ops(monkeypatch, ops)
    with Pipeline(settings, ctx=gl_context) as pipe, \
            Pipeline(other_settings, ctx=gl_context) as other:
        split, units, reports = units_of(pipe, settings, other, other_settings, ops)
    inject, geometry, propagate = ([unit[1] for unit in units if unit[0] == stage]
                                   for stage in STAGES)
    # the injection: the draw, then each channel's copy
    assert inject == [["draw_points_additively"]] + [["copy_volume"]] * 3
    assert [call[1:] for call in reports if call[0] == "inject"] == [(k, 4) for k in range(1, 5)]
    # the geometry volume: per view its draws and its two copies, each further view and the
    # camera's surfels (several views) merged in a unit of their own, then the read taken
    per_view = [["draw_points_additively"], ["copy_volume"], ["copy_volume"]]
    further = per_view + [["merge_volumes"]]
    expected = per_view + further * (views - 1 + (views > 1)) + [[]]
    assert geometry == expected
    assert [call[1:] for call in reports if call[0] == "geometry"] == [
        (k, len(expected)) for k in range(1, len(expected) + 1)]
    # the propagation: its start, grid_0's three channels into the accumulation, the steps
    assert propagate[:4] == [[], ["copy_volume"], ["copy_volume"], ["copy_volume"]]
    assert not any(propagate[4:])
    # the same grids, bit for bit
    level, level_whole = split.cascades[0], whole.cascades[0]
    assert np.abs(level.steps[0]).max() > 0 and np.abs(level.geometry_volume).max() > 0
    assert np.array_equal(level.steps[0], level_whole.steps[0])            # the injected grid
    assert np.array_equal(level.geometry_volume, level_whole.geometry_volume)
    for got, want in zip(level.steps, level_whole.steps):
        assert np.array_equal(got, want)
    assert np.array_equal(level.accumulated, level_whole.accumulated)
    assert np.array_equal(split.indirect, whole.indirect)


def test_a_small_grids_volumes_are_one_unit_each(gl_context, ctx, monkeypatch):
    """At 8³ (under ``APART_TEXELS``) the injection and each level's geometry volume are one
    unit and the propagation's start copies grid_0 itself."""
    settings = BASE.with_changes(lights=("spot", "lamp"))
    ops: list[str] = []
    record_ops(monkeypatch, ops)
    with Pipeline(settings, ctx=gl_context) as pipe, \
            Pipeline(settings, ctx=gl_context) as other:
        _, units, _ = units_of(pipe, settings, other, settings, ops)
    draws_and_copies = ["draw_points_additively"] + ["copy_volume"] * 2
    assert [unit[1] for unit in units if unit[0] != "propagate"] == [
        ["draw_points_additively"] + ["copy_volume"] * 3,                 # the injection
        draws_and_copies + draws_and_copies + ["merge_volumes"], []]      # two views, the read
    assert next(unit for unit in units if unit[0] == "propagate")[1] == ["copy_volume"] * 3


def test_a_heavy_kernels_steps_run_in_half_slabs_with_the_same_grid(gl_context, ctx,
                                                                   monkeypatch):
    """Two bounces, 26 neighbours or L2 (2–4× the slab's time) halve the slab, with
    ping-pong only (in place another split would change the race): a 64³ step is 16
    units, and a split step gives the one-slab grid bit for bit."""
    propagate = sys.modules["explorer.lpv.passes.propagate"]
    full = propagate.SLAB_CELLS
    assert propagate.kernel_slab_cells(True, 1, 6, 1) == full
    for heavy in ((True, 2, 6, 1), (True, 1, 26, 1), (True, 1, 6, 2)):
        assert propagate.kernel_slab_cells(*heavy) == full // 2
    assert propagate.kernel_slab_cells(False, 2, 26, 2) == full              # in place
    assert len(propagate.slabs(64, propagate.kernel_slab_cells(True, 2, 6, 1))) == 16
    assert len(propagate.slabs(64, propagate.kernel_slab_cells(True, 1, 6, 1))) == 8
    settings = BASE                                          # two bounces, ping-pong
    with Pipeline(settings, ctx=gl_context) as pipe:
        whole = pipe.run(settings)                           # 8³: one slab a step
        monkeypatch.setattr(propagate, "SLAB_CELLS", 8 * 8 * 8)  # a step, or two halves
        pipe.invalidate("propagate")
        calls = []
        job = pipe.start(settings, progress=lambda *call: calls.append(call))
        while not job.done:
            job.advance(0.0)                                 # one unit a call
        halves = job.result
    steps = [done for stage, done, _ in calls if stage == "propagate"]
    # the stage's start, the level's start, after each half of every step the steps done,
    # and the level's audit and read-back
    assert steps == [0, 0, 0] + sorted(2 * list(range(1, settings.iterations))) + [
        settings.iterations] * 3
    assert np.array_equal(halves.accumulated, whole.accumulated)
    assert np.array_equal(halves.indirect, whole.indirect)


@pytest.mark.parametrize("order, fmt", [(1, "rgba32f"), (2, "rgba32f"), (2, "rgba16f")])
def test_a_grid_taken_from_its_deferred_reads_is_the_grid_read(gl_context, ctx, monkeypatch,
                                                               order, fmt):
    """``LpvGrid.taken`` puts each channel's texels straight into the ``(3, x, y, z, C)``
    array, with no channel array made on the way (``VolumeTexture.texels``: a copy of a
    64³ channel): the same values, bit for bit, as the synchronous ``read`` and as the
    grid written (rounded to the format)."""
    from explorer.gl.gpu_sync import DeferredRead
    from explorer.lpv.passes import textures
    from explorer.lpv.passes.textures import LpvGrid

    cells = (5, 4, 3)
    grid = LpvGrid(gl_context, cells, fmt, order)
    reads = [DeferredRead(gl_context) for _ in range(3)]
    try:
        values = np.random.default_rng(7).normal(size=(3,) + cells + (grid.coefficients,))
        grid.write(values.astype(np.float32))
        grid.read_later(reads)
        with monkeypatch.context() as patched:
            patched.setattr(textures.VolumeTexture, "texels",
                            lambda *args: pytest.fail("texels called"))
            taken = grid.taken(reads)
        read = grid.read()
        assert taken.shape == read.shape == (3,) + cells + ((4, 9)[order - 1],)
        assert taken.dtype == np.float32 and taken.flags["C_CONTIGUOUS"]
        assert np.array_equal(taken, read) and np.abs(taken).max() > 0
        # read and taken share their layout code: the grid written is the independent side
        stored = np.float16 if fmt == "rgba16f" else np.float32
        written = values.astype(np.float32)                      # what write() uploads
        assert np.array_equal(taken, written.astype(stored).astype(np.float32))
    finally:
        for read_back in reads:
            read_back.release()
        grid.release()


@pytest.mark.parametrize("order", [1, 2])
def test_a_large_rsms_points_are_drawn_in_batches_with_the_same_grids(gl_context, ctx,
                                                                      monkeypatch, order):
    """More VPLs than ``POINT_BATCH`` are drawn in batches, a unit each (the injection's and
    the geometry volume's), with another pipeline's units between them: the sums are the
    one-draw sums bit for bit (GL blends in the points' order, across draws too)."""
    settings = BASE.with_changes(sh_order=order)              # a 32² RSM: 1024 VPLs
    other_settings = BASE.with_changes(grid_size=12, rsm_size=16)
    with Pipeline(settings, ctx=gl_context) as pipe:
        whole = pipe.run(settings, keep_steps=True)
    textures = sys.modules["explorer.lpv.passes.textures"]
    monkeypatch.setattr(textures, "POINT_BATCH", 300)
    assert textures.point_batches(1024) == [(0, 300), (300, 300), (600, 300), (900, 124)]
    assert textures.point_batches(0) == [(0, 0)]
    ops: list[str] = []
    record_ops(monkeypatch, ops)
    with Pipeline(settings, ctx=gl_context) as pipe, \
            Pipeline(other_settings, ctx=gl_context) as other:
        split, units, reports = units_of(pipe, settings, other, other_settings, ops)
    draw = "draw_points_additively"
    assert [unit[1] for unit in units if unit[0] == "inject"] == [[draw]] * 3 + [
        [draw] + ["copy_volume"] * 3]
    assert [call[1:] for call in reports if call[0] == "inject"] == [(k, 4) for k in range(1, 5)]
    # the geometry volume's surfels too (a small grid: the copies with the last batch)
    assert [unit[1] for unit in units if unit[0] == "geometry"] == [[draw]] * 3 + [
        [draw] + ["copy_volume"] * 2, []]
    assert [call[1:] for call in reports if call[0] == "geometry"] == [
        (k, 5) for k in range(1, 6)]
    assert np.array_equal(split.cascades[0].geometry_volume, whole.cascades[0].geometry_volume)
    assert np.abs(split.cascades[0].steps[0]).max() > 0
    assert np.array_equal(split.cascades[0].steps[0], whole.cascades[0].steps[0])
    assert np.array_equal(split.cascades[0].accumulated, whole.cascades[0].accumulated)
    assert np.array_equal(split.indirect, whole.indirect)


@pytest.mark.parametrize("apart", [0, 10 ** 9])
def test_batches_copies_and_merges_are_counted_as_they_run(gl_context, ctx, monkeypatch,
                                                           apart):
    """Two lights and camera occluders, in batches, with the volumes copied apart or not:
    the geometry stage's progress total is its units, and the grids are the one-shot
    ones."""
    settings = BASE.with_changes(lights=("spot", "lamp"), camera_occluders=True)
    with Pipeline(settings, ctx=gl_context) as pipe:
        whole = pipe.run(settings, keep_steps=True)
    textures = sys.modules["explorer.lpv.passes.textures"]
    monkeypatch.setattr(textures, "POINT_BATCH", 300)     # 1024 VPLs a view, 1280 pixels
    monkeypatch.setattr(textures, "APART_TEXELS", apart)
    ops: list[str] = []
    record_ops(monkeypatch, ops)
    with Pipeline(settings, ctx=gl_context) as pipe, \
            Pipeline(BASE, ctx=gl_context) as other:
        split, units, reports = units_of(pipe, settings, other, BASE, ops)
    geometry = [unit[1] for unit in units if unit[0] == "geometry"]
    totals = {call[2] for call in reports if call[0] == "geometry"}
    assert totals == {len(geometry)}
    # two views of 4 batches, the camera's 5, two copies each and two merges
    flat = [op for unit in geometry for op in unit]
    assert flat.count("draw_points_additively") == 13 and flat.count("merge_volumes") == 2
    assert all(len(unit) <= 1 for unit in geometry) == (apart == 0)
    level, level_whole = split.cascades[0], whole.cascades[0]
    assert np.array_equal(level.geometry_volume, level_whole.geometry_volume)
    assert np.array_equal(level.accumulated, level_whole.accumulated)
