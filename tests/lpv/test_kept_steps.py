"""What a frame at a big grid leaves behind: the kept propagation steps
(explorer/lpv/kept_steps.py), each held as its box of cells with light and read back bit
for bit, a frame of light in flight from a small source holding a small part of its
steps' whole grids; and the audit's buffers, not kept at a big grid's size for a small
one."""

from __future__ import annotations

import numpy as np

from explorer.lpv.kept_steps import KeptSteps
from explorer.lpv.pipeline import Pipeline
from explorer.lpv.settings import Settings


def _steps() -> list[np.ndarray]:
    rng = np.random.default_rng(7)
    grids = []
    for lo, hi in (((3, 4, 5), (6, 8, 7)), ((0, 0, 0), (10, 9, 8)), ((2, 2, 2), (3, 3, 3))):
        grid = np.zeros((3, 10, 9, 8, 4), np.float32)
        box = (slice(None),) + tuple(slice(a, b) for a, b in zip(lo, hi))
        grid[box] = rng.normal(size=grid[box].shape).astype(np.float32)
        grids.append(grid)
    grids[0][1, 7, 1, 1, 2] = -0.0          # not zero bits: inside the box, kept as -0.0
    grids[2][0, 9, 8, 7, 3] = np.nan
    grids.append(np.zeros((3, 10, 9, 8, 4), np.float32))      # no light at all
    return grids


def test_every_step_reads_back_bit_for_bit():
    grids = _steps()
    kept = KeptSteps(grids)
    assert len(kept) == len(grids)
    for t, grid in enumerate(grids):
        for got in (kept[t], kept[t - len(grids)], list(kept)[t], kept[t:t + 1][0]):
            assert got.shape == grid.shape and got.dtype == grid.dtype
            assert np.array_equal(got.view(np.uint32), grid.view(np.uint32))
            assert not got.flags.writeable
        for index in ((7, 1, 1), (9, 8, 7), (0, 0, 0), (4, 5, 6)):
            assert np.array_equal(kept.cell(index)[t].view(np.uint32),
                                  grid[(slice(None),) + index].view(np.uint32))
    assert kept.nbytes < sum(grid.nbytes for grid in grids)


def test_light_in_flight_from_a_small_source_keeps_its_boxes_only(gl_context):
    settings = Settings(scene="single-source", grid_size=32, iterations=6, rsm_size=32,
                        width=48, height=36)
    with Pipeline(settings, ctx=gl_context) as pipeline:
        steps = pipeline.run(settings, keep_steps=True).steps
        assert steps is not None and len(steps) == 7
        whole = sum(step.nbytes for step in steps)
        # a patch's light reaches 6 cells a side after 6 steps: each box is a small part
        # of the 32³ grid
        assert steps.nbytes < whole / 4


def test_the_audit_does_not_keep_a_big_grids_buffers_for_a_small_one(ctx):
    """A 64³ grid's per-cell audit records (42 MiB) are given back when an 8³ grid
    follows (whose steps' records, kept for one reduction of a unit's steps, take at most
    ``KEPT_RECORDS_BYTES``), and a grid of about the same size reuses the buffers it
    has."""
    from explorer.gl.program import ProgramCache
    from explorer.lpv.passes.audit_reduce import KEPT_RECORDS_BYTES, SHRINK_OVER, AuditReducer

    audit = AuditReducer(ctx, ProgramCache(ctx))
    try:
        audit.begin(64, 18)
        big = {name: buffer.size for name, buffer in audit._buffers.items()}
        audit.begin(8, 18)
        small = {name: buffer.size for name, buffer in audit._buffers.items()}
        assert small.keys() == big.keys()
        assert small["cells"] <= KEPT_RECORDS_BYTES < big["cells"]
        assert sum(size for name, size in small.items() if name != "cells") * 64 < \
            sum(big.values())
        kept = dict(audit._buffers)
        audit.begin(7, 18)                    # within SHRINK_OVER of 8³: nothing made anew
        assert SHRINK_OVER * 7 ** 3 > 8 ** 3
        assert all(audit._buffers[name] is kept[name] for name in kept)
    finally:
        audit.release()
