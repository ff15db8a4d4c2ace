"""The program cache keeps at most ``capacity`` programs and releases the least recently
used; a propagation that spans frames survives its program being released meanwhile."""

from __future__ import annotations

import moderngl
import numpy as np
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


def test_a_propagation_keeps_running_when_the_cache_released_its_program(ctx):
    """Other programs got between two slabs (a window's frames) push the run's program
    out of a cache of two; the run gets it anew, with its uniforms, and the result is
    the twin's."""
    grid = random_grid(5, 8)
    spec = GridSpec((0.0, 0.0, 0.0), 1.0, 8)
    cache = ProgramCache(ctx, capacity=2)
    injected = LpvGrid(ctx, 8)
    propagator = PropagatePass(ctx, cache)
    try:
        injected.write(grid)
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
    finally:
        propagator.release()
        injected.release()
        cache.release()
