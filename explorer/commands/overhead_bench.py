"""``lpv-explorer bench --overhead``: what a frame costs besides the GPU's work, on sizes
where that work is negligible (an 8³ grid, a 64² image and RSM unless given).

Each row re-runs one kind of frame ``--repeat`` times (default
:data:`DEFAULT_FRAMES`) with the moderngl calls counted (:class:`GlCallCounter`) and
prints per frame: the wall time, the Python time outside GL calls (the CPU side a GPU
would not hide), and the GL calls, dispatches, draws, barriers, finishes, read-backs,
uniform uploads and bindings issued. Rows (:data:`FRAMES`): ``full`` (every stage from
the RSM on, as ``bench`` times a frame), ``light`` (a correction or the light changed:
from the injection on), ``camera`` (the camera moved: G-buffer, gather, display) and
``display`` (an exposure change: the display pass only).
"""

from __future__ import annotations

import argparse
import time

from explorer.commands import options
from explorer.gl.call_counter import GlCallCounter

DEFAULT_FRAMES = 20
TINY = {"grid_size": 8, "width": 64, "height": 64, "rsm_size": 64}
"""Sizes of the overhead rows unless --grids, --size or --rsm-size give others."""
FRAMES = (("full", "rsm"), ("light", "inject"), ("camera", "gbuffer"), ("display", "display"))
"""Row name -> the first stage it re-runs (``Pipeline.invalidate``)."""
COUNTED = ("GL calls", "dispatches", "draws", "barriers", "finishes", "read-backs",
           "uniform uploads", "bindings")


def tiny_settings(args: argparse.Namespace):
    """The settings of the overhead rows: the command line's, with :data:`TINY` sizes
    where it gives none."""
    base = options.settings_from_args(args)
    changes = {"grid_size": (args.grid_size or (TINY["grid_size"],))[0]}
    if args.size is None:
        changes.update(width=TINY["width"], height=TINY["height"])
    if args.rsm_size is None:
        changes["rsm_size"] = TINY["rsm_size"]
    return base.with_changes(**changes)


def measure_overhead(pipeline, settings, frames: int) -> list[dict]:
    """One row per entry of :data:`FRAMES`: per-frame wall and outside-GL milliseconds,
    call counts, and the outside-GL milliseconds by stage (``python_by_stage_ms``: each
    unit of work's; ``job`` is the time between units), over ``frames`` frames after two
    warm-up frames."""
    options.run_pipeline(pipeline, settings)
    options.run_pipeline(pipeline, settings)
    rows = []
    for name, first_stage in FRAMES:
        wall = 0.0
        with GlCallCounter() as counter, _UnitTimes(counter) as units:
            for _ in range(frames):
                pipeline.invalidate(first_stage)
                start = time.perf_counter()
                options.run_pipeline(pipeline, settings)
                wall += time.perf_counter() - start
        per_frame = counter.tally.per(frames)
        outside_ms = (wall - counter.tally.inside_s) / frames * 1e3
        by_stage = {stage: ms / frames for stage, ms in units.python_ms.items()}
        by_stage["job"] = max(outside_ms - sum(by_stage.values()), 0.0)
        rows.append({"frame": name, "reruns_from": first_stage,
                     "wall_ms": wall / frames * 1e3, "outside_gl_ms": outside_ms,
                     "counts": {kind: per_frame.get(kind, 0.0) for kind in COUNTED},
                     "python_by_stage_ms": by_stage})
    return rows


class _UnitTimes:
    """While active, the Python milliseconds (outside the counted GL calls) of every unit
    of a job, summed by stage: ``Job._run_unit`` wrapped (one job's units at a time)."""

    def __init__(self, counter: GlCallCounter) -> None:
        self.counter = counter
        self.python_ms: dict[str, float] = {}

    def __enter__(self) -> "_UnitTimes":
        from explorer.lpv.job import Job

        self._original = original = Job._run_unit
        tally, totals = self.counter.tally, self.python_ms

        def timed_unit(job) -> None:
            stage, inside, start = job.stage, tally.inside_s, time.perf_counter()
            try:
                original(job)
            finally:
                spent = time.perf_counter() - start - (tally.inside_s - inside)
                totals[stage] = totals.get(stage, 0.0) + spent * 1e3

        Job._run_unit = timed_unit
        return self

    def __exit__(self, *exc_info) -> None:
        from explorer.lpv.job import Job

        Job._run_unit = self._original


def format_overhead(rows: list[dict]) -> str:
    header = ["frame", "wall ms", "python ms", *COUNTED]
    widths = [8, 9, 10] + [max(9, len(kind)) for kind in COUNTED]
    lines = ["  ".join(f"{h:>{w}}" for h, w in zip(header, widths))]
    for row in rows:
        cells = [row["frame"], f"{row['wall_ms']:.2f}", f"{row['outside_gl_ms']:.2f}"]
        cells += [f"{row['counts'][kind]:.0f}" for kind in COUNTED]
        lines.append("  ".join(f"{c:>{w}}" for c, w in zip(cells, widths)))
    for row in rows:
        stages = sorted(row["python_by_stage_ms"].items(), key=lambda item: -item[1])
        lines.append(f"  python ms of a {row['frame']} frame by stage: " + ", ".join(
            f"{stage} {ms:.2f}" for stage, ms in stages if ms >= 0.005))
    return "\n".join(lines)
