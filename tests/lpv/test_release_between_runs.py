"""What only a propagation in progress uses (its ping and pong grids) is released when the
window falls idle (issue #31 item 6: a 64³ frame with two cascades and a second side kept
twelve such grids, 120 MiB, between runs), never while a run uses them, and the frames
after it are the frames of a pipeline that kept them, bit for bit."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

import explorer.lpv.passes.propagate as propagate_pass
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings

BASE = Settings(scene="cornell", grid_size=8, iterations=4, rsm_size=32, width=40, height=32,
                cascades=2)


def _same(a, b) -> None:
    assert np.array_equal(a.indirect, b.indirect, equal_nan=True)
    for level_a, level_b in zip(a.cascades, b.cascades, strict=True):
        assert np.array_equal(level_a.accumulated, level_b.accumulated, equal_nan=True)


def test_idle_release_keeps_the_frames_bit_for_bit(ctx, monkeypatch):
    monkeypatch.setattr(propagate_pass, "SPARE_GRID_BYTES", 0)     # every grid is large
    toggled = BASE.with_changes(corrections=replace(
        BASE.corrections, clamp_front_face=not BASE.corrections.clamp_front_face))
    with Pipeline(BASE, ctx=ctx) as kept, Pipeline(BASE, ctx=ctx) as released:
        first_kept, first_released = kept.run(BASE), released.run(BASE)
        _same(first_kept, first_released)
        freed = released.release_between_runs()
        # two levels, each its ping and pong (three 8³ RGBA float textures a grid) and
        # the read-back of its accumulation (three more), and the injection's layers
        assert freed == (2 * 3 + 1) * 3 * 8 ** 3 * 16
        assert released.release_between_runs() == 0                  # nothing left to free
        _same(kept.run(toggled), released.run(toggled))
        _same(kept.run(BASE), released.run(BASE))


def test_no_release_while_a_run_is_in_progress(ctx, monkeypatch):
    monkeypatch.setattr(propagate_pass, "SPARE_GRID_BYTES", 0)
    with Pipeline(BASE, ctx=ctx) as reference:
        expected = reference.run(BASE)
    with Pipeline(BASE, ctx=ctx) as pipeline:
        job = pipeline.start(BASE)
        while not any(level.running is not None and level.running.done
                      for level in pipeline.state.levels):
            job.advance(0.0)
        assert pipeline.release_between_runs() == 0                  # the job is not done
        while not job.done:
            job.advance(None)
        _same(job.result, expected)
        assert pipeline.release_between_runs() > 0


def test_small_grids_stay():
    """A 48³ L1 grid (5 MiB) is kept between runs: making it again would cost more than
    it holds (SPARE_GRID_BYTES)."""
    assert 3 * 48 ** 3 * 16 < propagate_pass.SPARE_GRID_BYTES <= 3 * 64 ** 3 * 16


def test_the_threshold_is_a_whole_grids(ctx, monkeypatch):
    """The threshold holds a grid's three channels together: a 64³ L1 grid's read-back
    is three reads of 4 MiB, 12 MiB as the grid (each alone below 8 MiB stayed)."""
    one_grid = 3 * 8 ** 3 * 16
    monkeypatch.setattr(propagate_pass, "SPARE_GRID_BYTES", one_grid)
    with Pipeline(BASE, ctx=ctx) as pipeline:
        pipeline.run(BASE)
        # per level ping, pong and the read-back; the injection's layers once
        assert pipeline.release_between_runs() == (2 * 3 + 1) * one_grid
    monkeypatch.setattr(propagate_pass, "SPARE_GRID_BYTES", one_grid + 1)
    with Pipeline(BASE, ctx=ctx) as pipeline:
        pipeline.run(BASE)
        assert pipeline.release_between_runs() == 0
