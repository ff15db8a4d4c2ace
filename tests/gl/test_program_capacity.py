"""The program cache keeps at most ``capacity`` programs and releases the least recently
used; a propagation that spans frames survives its program being released meanwhile."""

from __future__ import annotations

from contextlib import contextmanager

import moderngl
import numpy as np
import pytest
from lpv_cases import random_grid, relative_error

from explorer.gl.program import ProgramCache
from explorer.lpv.grid import GridSpec
from explorer.lpv.passes.propagate import PropagatePass, program_defines
from explorer.lpv.passes.textures import LpvGrid
from explorer.lpv.settings import Corrections
from explorer.lpv.twin import light_grid as twin


def _released(program) -> bool:
    return isinstance(program.mglo, moderngl.InvalidObject)


def _variant(cache: ProgramCache, stage: int):
    return cache.get("audit_reduce.glsl", {"AUDIT_STAGE": stage})


@contextmanager
def _propagation_in_a_cache_of_two(ctx, seed: int):
    """A propagator over a program cache of capacity 2 and an 8³ random injected grid:
    (grid, spec, cache, injected, propagator), all released after."""
    grid = random_grid(seed, 8)
    cache = ProgramCache(ctx, capacity=2)
    injected = LpvGrid(ctx, 8)
    propagator = PropagatePass(ctx, cache)
    try:
        injected.write(grid)
        yield grid, GridSpec((0.0, 0.0, 0.0), 1.0, 8), cache, injected, propagator
    finally:
        propagator.release()
        injected.release()
        cache.release()


def test_the_least_recently_used_program_beyond_the_capacity_is_released(ctx):
    cache = ProgramCache(ctx, capacity=2)
    try:
        first, second = _variant(cache, 0), _variant(cache, 1)
        assert _variant(cache, 0) is first          # used again: now the most recent
        third = _variant(cache, 2)
        assert len(cache) == 2
        assert _released(second) and not _released(first) and not _released(third)
        assert _variant(cache, 1) is not second     # compiled anew when asked again
        assert _released(first) and len(cache) == 2
    finally:
        cache.release()


def test_the_cache_counts_the_programs_it_releases(ctx):
    """``releases`` changes whenever a program got before may no longer be the cache's
    (what the callers that keep a program compare)."""
    cache = ProgramCache(ctx, capacity=2)
    try:
        _variant(cache, 0), _variant(cache, 1), _variant(cache, 0)
        assert cache.releases == 0                  # got again: nothing left
        _variant(cache, 2)
        assert cache.releases == 1                  # stage 1 evicted
        cache.release()
        assert cache.releases == 3
    finally:
        cache.release()


def test_slabs_of_one_unit_get_the_programs_anew_after_the_cache_released_them(ctx):
    """Within a unit (``advance(bound=True)``) a run keeps its program and the audit its
    reduction's; a release in the cache in between (here: a compile pushing both out of
    a cache of two) makes them get theirs anew, and the result is the twin's."""
    with _propagation_in_a_cache_of_two(ctx, 6) as (grid, spec, cache, injected, propagator):
        run = propagator.start(injected, spec, Corrections(), 3)
        run.advance()
        kept = run._program
        for stage in (0, 2):                      # not the per-step reduction's stage 1
            _variant(cache, stage)
        assert _released(kept)
        while not run.finished:
            run.advance(bound=True)
        assert run._program is not kept
        output = run.finish()
        want = sum(twin.propagate(grid, Corrections(), 3))
        assert relative_error(output.accumulated.read(), want) < 1e-4
        full = propagator.run(injected, spec, Corrections(), 3)      # the same, fresh
        assert np.array_equal(output.audit.per_step, full.audit.per_step)


def test_a_propagation_keeps_running_when_the_cache_released_its_program(ctx):
    """Other programs got between two slabs (a window's frames) push the run's program
    out of a cache of two; the run gets it anew, with its uniforms, and the result is
    the twin's."""
    with _propagation_in_a_cache_of_two(ctx, 5) as (grid, spec, cache, injected, propagator):
        run = propagator.start(injected, spec, Corrections(), 3)
        # the program the run started with (audit "full": the audit kernel)
        started = cache.get("propagate.glsl", program_defines("rgba32f", 1, Corrections(),
                                                              audit=True))
        while not run.finished:
            run.advance()
            for stage in (0, 1, 2):               # the frame's other programs
                _variant(cache, stage)
        assert _released(started)
        output = run.finish()
        want = sum(twin.propagate(grid, Corrections(), 3))
        assert relative_error(output.accumulated.read(), want) < 1e-4
        assert np.isfinite(output.accumulated.read()).all()


@pytest.mark.parametrize("image_units", [None, 8])
def test_steps_in_a_row_in_a_cache_too_small_for_their_programs_step_as_usual(
        ctx, monkeypatch, image_units):
    """A unit's steps in a row get a second program (ping and pong on units of their own;
    with 8 image units none) and the audit's: in a cache of two that releases programs, so
    the unit steps as ``advance`` does instead, and the result is the one of a roomy cache,
    bit for bit."""
    import time

    with _propagation_in_a_cache_of_two(ctx, 7) as (grid, spec, cache, injected, propagator):
        if image_units is not None:
            monkeypatch.setattr(propagator, "image_units", lambda: image_units)
        run = propagator.start(injected, spec, Corrections(), 6)
        while not run.finished:
            run.advance_for(1e9, time.perf_counter())
        small = run.finish()
        accumulated, per_step = small.accumulated.read(), small.audit.per_step.copy()
    roomy = PropagatePass(ctx, ProgramCache(ctx))
    try:
        grid_texture = LpvGrid(ctx, 8)
        grid_texture.write(grid)
        output = roomy.run(grid_texture, spec, Corrections(), 6)
        assert np.array_equal(output.accumulated.read(), accumulated)
        assert np.array_equal(output.audit.per_step, per_step)
        grid_texture.release()
    finally:
        roomy.release()
