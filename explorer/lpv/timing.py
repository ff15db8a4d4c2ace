"""How long each pass of a frame took on the GPU (:class:`PassTimer`).

On a GPU every pass is timed with a GL timer query (``ctx.query(time=True)``). Mesa's
llvmpipe reads 0 around compute dispatches and, around draws, either 2³²−1 (no result) or
a few microseconds of command submission (it rasterises on worker threads later), so on a
software renderer every pass is timed with the wall clock between two ``ctx.finish()``
calls. A query that reads 0 or 2³²−1 falls back to the wall clock too.
:attr:`PassTimer.methods` records which method timed each pass.

``queued`` (the default on a GPU): no ``finish`` around a pass; its timer query is read
once the GPU has the result (explorer/gl/gpu_sync.py ``TimerQueries``, usually a frame
later) and :attr:`PassTimer.timings_ms` then holds the latest finished value; what a
unit of a job costs the CPU is then its wall time (the GPU works in parallel). On a
software renderer the CPU is the GPU: its passes are waited for, since that wall clock is
the only truthful time there. ``bench`` times synchronously (``queued`` False), and
:meth:`PassTimer.measure` always is.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import TypeVar

import moderngl

from explorer.gl.gpu_sync import TimerQueries

QUERY_UNAVAILABLE_MS = (2**32 - 1) / 1e6
"""A timer query that reads 2³²−1 ns has no result (Mesa answers so on first use)."""
SOFTWARE_RENDERERS = ("llvmpipe", "softpipe", "swrast", "lavapipe")
"""Substrings of ``GL_RENDERER`` (lower case) that name a software renderer."""

T = TypeVar("T")


def is_software_renderer(ctx: moderngl.Context) -> bool:
    """Whether ``ctx`` renders in software (its timer queries are then not used)."""
    renderer = str(ctx.info.get("GL_RENDERER", "")).lower()
    return any(name in renderer for name in SOFTWARE_RENDERERS)


class PassTimer:
    """Times passes and keeps the last time and method of each (module docstring)."""

    def __init__(self, ctx: moderngl.Context, queued: bool | None = None) -> None:
        self.ctx = ctx
        self.software_renderer = is_software_renderer(ctx)
        self.queued = not self.software_renderer if queued is None else queued
        """Passes are not waited for (module docstring)."""
        self._timer_queries: TimerQueries | None = None
        self._generation: dict[str, int] = {}
        """Pass name -> how many times it was reset (a late result of an older run of an
        accumulated stage is not added to the new one)."""
        self.timings_ms: dict[str, float] = {}
        """Pass name -> milliseconds of its last run (a stage of several units: their sum)."""
        self.methods: dict[str, str] = {}
        """Pass name -> "timer-query" or "wall-clock"."""
        self._queries: dict[str, moderngl.Query] = {}
        """One query object per pass name, reused: moderngl cannot free them."""

    def measure(self, name: str, work: Callable[[], T]) -> tuple[T, float, str]:
        """``(work(), milliseconds, method)``: the GPU time of ``work`` by a timer query
        or, on a software renderer or without a query result, the wall clock between two
        ``ctx.finish()`` calls. Records nothing."""
        self.ctx.finish()
        start = time.perf_counter()
        query = None
        if not self.software_renderer:
            query = self._queries.get(name)
            if query is None:
                query = self._queries[name] = self.ctx.query(time=True)
        if query is None:
            result = work()
        else:
            with query:
                result = work()
        self.ctx.finish()
        wall_ms = (time.perf_counter() - start) * 1e3
        query_ms = 0.0 if query is None else query.elapsed / 1e6
        if 0.0 < query_ms < QUERY_UNAVAILABLE_MS:
            return result, query_ms, "timer-query"
        return result, wall_ms, "wall-clock"

    def timed(self, name: str, work: Callable[[], T], accumulate: bool = False) -> T:
        """Run ``work()`` and record its time in ``timings_ms[name]``; ``accumulate`` adds
        it to the time recorded so far (a stage of several units, after :meth:`reset`).
        Queued: the GPU time is recorded when its query's result arrives (:meth:`collect`)."""
        if self.queued:
            return self._queued(name, work, accumulate)
        result, elapsed, self.methods[name] = self.measure(name, work)
        self.timings_ms[name] = elapsed + (self.timings_ms.get(name, 0.0) if accumulate
                                           else 0.0)
        return result

    def _queued(self, name: str, work: Callable[[], T], accumulate: bool) -> T:
        if self._timer_queries is None:
            self._timer_queries = TimerQueries()
        query = self._timer_queries.begin()
        try:
            return work()
        finally:
            self._timer_queries.end(query, (name, self._generation.get(name, 0), accumulate))

    def collect(self, wait: bool = False) -> None:
        """Record the results of the timer queries the GPU has finished (``wait``: all
        of them, waiting for the GPU: a benchmark that needs this frame's times). Asked
        once a stage starts (:meth:`reset`): each ask is a driver call."""
        if self._timer_queries is None:
            return
        for (name, generation, accumulate), ms in self._timer_queries.collect(wait):
            if generation != self._generation.get(name, 0):
                continue
            self.methods[name] = "timer-query"
            self.timings_ms[name] = ms + (self.timings_ms.get(name, 0.0) if accumulate
                                          else 0.0)

    def reset(self, name: str) -> None:
        """Start ``name``'s time at 0 (its units then :meth:`timed` with ``accumulate``)."""
        self.collect()
        self._generation[name] = self._generation.get(name, 0) + 1
        self.timings_ms[name] = 0.0

    def forget(self, name: str) -> None:
        """Drop ``name``'s time: the pass did not run in this frame's configuration."""
        self.timings_ms.pop(name, None)
